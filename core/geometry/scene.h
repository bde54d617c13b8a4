#pragma once
/// Where meshes come from: an OBJ file path, or a built-in scene "builtin:NAME?k=v&k=v".
///
/// Implemented in obj_loader.cpp (load_obj), builtin_scenes.cpp (make_builtin,
/// builtin_scenes, the Bézier evaluation), teapot_patches.cpp (the teapot's
/// control points) and scene.cpp (load_scene).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/util/expected.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// Loads an OBJ file through tinyobjloader; polygons are fan-triangulated
/// (a polygon v0 v1 ... v(k-1) gives the k-2 triangles (v0, vi, vi+1)), in file order.
/// Only `v` and `f` matter: normals, texture coordinates, groups and materials
/// are ignored (a missing .mtl is not an error). Negative (relative) indices are
/// allowed. Mesh.name is `path`.
/// Errors (one line) name the file and, where known, the line, as
/// "PATH:LINE: reason": missing, unreadable (e.g. a directory), empty (no
/// triangles), malformed (a bad or missing number or a non-finite coordinate in a
/// `v` line; a face index that is zero, not an integer or out of range; a face
/// with fewer than 3 vertices). Never throws. `progress` counts three passes over
/// the file's bytes and may cancel the load (WorkProgress::cancelled_error()).
Expected<Mesh> load_obj(const std::string& path, WorkProgress* progress = nullptr);

/// An OBJ file's objects: the runs of faces between `o` and `g` statements, in file
/// order (faces before the first statement make object 0; statements with no faces
/// between them name one object), with their triangles in load_obj's numbering.
struct ObjObject {
    std::string name;  ///< the statement's text ("" before the first)
    size_t first_triangle = 0, triangle_count = 0;
};
/// The objects of the OBJ file at `path` (one more pass over its lines; the file is
/// assumed to load: load_obj checks it).
Expected<std::vector<ObjObject>> obj_objects(const std::string& path);

/// load_obj of OBJ text held in memory; `name` stands for the path in messages.
Expected<Mesh> parse_obj(std::string text, const std::string& name);

/// A built-in scene, e.g. "cube", "cornell", "teapot?n=8", "soup?n=1000&seed=7".
/// `spec` is what follows "builtin:". Unknown names or parameters, values that are
/// not numbers or lie out of range are errors whose message lists what is accepted.
/// Mesh.name is "builtin:" + spec. The output depends only on `spec`: identical
/// on every machine: seeded scenes use Rng (core/util/random.h), and all arithmetic
/// is correctly rounded IEEE (+ - * / sqrt; no sin, cos or pow). `progress` follows
/// (and may cancel) the load of a scene another is made from (instances' mesh=), which
/// reads the mesh cache as default_mesh_cache() says (the overload below: as `cache`).
Expected<Mesh> make_builtin(const std::string& spec, WorkProgress* progress = nullptr);

/// A moving built-in scene (one with a time parameter t: builtin:moving,
/// builtin:wave) at time t: `source` with its t= set, e.g. "builtin:moving?n=4" at
/// 0.5 is "builtin:moving?n=4&t=0.5". Any other source is an error naming the moving
/// scenes (the program's --time flag).
Expected<std::string> scene_at_time(const std::string& source, double t);
/// The time t of a moving built-in scene (0 when its t= is not given); nothing for
/// any other source, or a t= that is not a number.
std::optional<double> scene_time(const std::string& source);

/// `one` repeated nx x nz times on a grid in the x-z plane, copies 1.1 times the
/// mesh's extent apart so that none overlap: builtin:instances, and the scaling
/// chart's scenes. Errors: more copies than 32-bit indices hold; cancelled.
Expected<Mesh> repeat_on_grid(const Mesh& one, uint64_t nx, uint64_t nz, WorkProgress* progress = nullptr);

/// The names make_builtin accepts, each with a one-line description and its parameters.
struct BuiltinInfo {
    std::string name;
    std::string description;
};
const std::vector<BuiltinInfo>& builtin_scenes();

/// Whether load_scene may use the mesh cache (core/geometry/mesh_cache.h) for OBJ
/// files. The program turns it on for the whole process (its --no-cache flag
/// leaves it off); until then load_scene touches no file but the one asked for.
enum class MeshCache { Skip, Use };
void set_default_mesh_cache(MeshCache cache);
MeshCache default_mesh_cache();

/// make_builtin, with the mesh cache of a scene made from another (instances) as `cache`.
Expected<Mesh> make_builtin(const std::string& spec, WorkProgress* progress, MeshCache cache);

/// "builtin:..." → make_builtin, anything else → load_obj (or its cached copy, see
/// load_obj_cached). Errors: an empty source, what those report, and a mesh the
/// program cannot show faithfully: every triangle of zero area (nothing to draw), a
/// coordinate beyond ±kMaxCoordinate or a scene less than kMinSceneSize across (mesh.h).
/// `progress` follows (and may cancel) an OBJ's parse, also the one inside
/// builtin:instances; a cached copy or another built-in scene is made without a check.
Expected<Mesh> load_scene(const std::string& source, MeshCache cache, WorkProgress* progress = nullptr);
/// load_scene with default_mesh_cache().
Expected<Mesh> load_scene(const std::string& source);

/// load_obj through the mesh cache in `cache_dir`: a valid copy of this version of
/// the file if there is one (`*from_cache` says so), else the parsed file, whose
/// copy is then written.
Expected<Mesh> load_obj_cached(const std::string& path, const std::filesystem::path& cache_dir,
                               bool* from_cache = nullptr, WorkProgress* progress = nullptr);

/// "k of N triangles have zero area ...", for stderr and the Stats panel (none: nullopt).
std::optional<std::string> degenerate_note(const Mesh& mesh);

// ---------------------------------------------------------------------------
// Bézier patches (the teapot)
// ---------------------------------------------------------------------------

/// A bicubic Bézier patch: 4 x 4 control points, control[i][j] weighted by
/// B_i(u) B_j(v) with the cubic Bernstein polynomials B_k(t) = C(3,k) t^k (1-t)^(3-k).
/// The patch passes through its four corner control points.
struct BezierPatch {
    Vec3 control[4][4];
};

/// The point of `patch` at (u, v) in [0,1]^2: the Bernstein form evaluated in
/// double precision and rounded once to float. At u or v equal to 0 or 1 the
/// result depends only on that edge's four control points, so two patches that
/// share an edge produce bit-identical points along it.
Vec3 bezier_patch_point(const BezierPatch& patch, double u, double v);

/// Newell's teapot (1975) as the 28 patches of geomview's teapot.bez, z up:
/// 0-3 rim, 4-7 upper body, 8-11 lower body, 12-15 handle, 16-19 spout,
/// 20-23 lid knob (each collapses to the knob's top point along control row 0),
/// 24-27 lid. No bottom. Bounds of the control points: x in [-0.25, 1.38125],
/// y in [-0.5, 0.5], z in [0.300049, 1.050049]; the body's axis is x = 0.5, y = 0.
/// Patches that share an edge list its control points in the same order.
constexpr int kTeapotPatchCount = 28;
/// The kTeapotPatchCount patches (a static table).
const BezierPatch* teapot_patches();

}  // namespace accelviz
