// load_scene: the one entry point the CLI and the window use for a scene source.
#include "core/geometry/scene.h"

#include "core/geometry/mesh_cache.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <optional>

namespace accelviz {

namespace {

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

/// A loaded mesh the program cannot show faithfully: nothing to draw, or a scale
/// beyond what float ray–triangle tests handle (see kMaxCoordinate).
std::optional<Error> check_drawable(const Mesh& mesh, const std::string& source) {
    const size_t n = mesh.triangle_count();
    if (n == 0) return std::nullopt;  // builtin:empty, kept for the degenerate-scene tests
    if (count_degenerate_triangles(mesh) == n)
        return Error{source + ": all " + std::to_string(n) + " triangle" + (n == 1 ? " has" : "s have") +
                     " zero area (corners that coincide or lie on one line): nothing to draw"};
    const Aabb box = mesh.bounds();
    double largest = 0, longest_side = 0;
    for (int a = 0; a < 3; ++a) {
        largest = std::max({largest, std::fabs(double(box.lo[a])), std::fabs(double(box.hi[a]))});
        longest_side = std::max(longest_side, double(box.hi[a]) - double(box.lo[a]));
    }
    if (largest > kMaxCoordinate)
        return Error{source + ": a vertex coordinate of " + number(largest) + " is beyond +-" + number(kMaxCoordinate) +
                     ", where the float ray-triangle test overflows (scale the scene down)"};
    if (longest_side < kMinSceneSize)
        return Error{source + ": the scene is " + number(longest_side) + " across, less than " + number(kMinSceneSize) +
                     ", where the float ray-triangle test loses its digits (scale the scene up)"};
    return std::nullopt;
}

}  // namespace

namespace {
std::atomic<MeshCache> process_mesh_cache{MeshCache::Skip};
}  // namespace

void set_default_mesh_cache(MeshCache cache) { process_mesh_cache = cache; }
MeshCache default_mesh_cache() { return process_mesh_cache; }

Expected<Mesh> load_scene(const std::string& source) { return load_scene(source, default_mesh_cache()); }

Expected<Mesh> load_obj_cached(const std::string& path, const std::filesystem::path& cache_dir, bool* from_cache,
                               WorkProgress* progress) {
    if (from_cache) *from_cache = false;
    const std::optional<ObjKey> key = obj_key(path);
    if (!key) return load_obj(path, progress);  // its message says what is wrong with the file
    const std::filesystem::path file = mesh_cache_file(cache_dir, *key);
    if (std::optional<Mesh> cached = read_mesh_cache(file, *key, path)) {
        if (from_cache) *from_cache = true;
        return std::move(*cached);
    }
    Expected<Mesh> mesh = load_obj(path, progress);
    if (mesh) write_mesh_cache(file, *key, *mesh, progress);
    if (cancelled(progress)) return WorkProgress::cancelled_error();  // (the copy not written)
    return mesh;
}

Expected<Mesh> load_scene(const std::string& source, MeshCache cache, WorkProgress* progress) {
    constexpr std::string_view kBuiltinPrefix = "builtin:";
    if (source.empty()) return Error{"no scene given (want an OBJ file or builtin:NAME)"};
    const std::optional<std::filesystem::path> cache_dir =
        cache == MeshCache::Use ? default_mesh_cache_dir() : std::nullopt;
    Expected<Mesh> mesh = source.starts_with(kBuiltinPrefix) ? make_builtin(source.substr(kBuiltinPrefix.size()), progress, cache)
                          : cache_dir                        ? load_obj_cached(source, *cache_dir, nullptr, progress)
                                                             : load_obj(source, progress);
    if (!mesh) return mesh;
    if (auto err = check_drawable(*mesh, source)) return *err;
    return mesh;
}

std::optional<std::string> degenerate_note(const Mesh& mesh) {
    const size_t degenerate = count_degenerate_triangles(mesh);
    if (degenerate == 0) return std::nullopt;
    return std::to_string(degenerate) + " of " + std::to_string(mesh.triangle_count()) +
           " triangles have zero area (corners that coincide or lie on one line): no ray hits them";
}

}  // namespace accelviz
