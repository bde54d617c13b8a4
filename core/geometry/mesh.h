#pragma once
/// A triangle mesh: shared vertex positions and index triples.

#include <span>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry/triangle.h"
#include "core/util/work_progress.h"

namespace accelviz {

struct Mesh {
    std::string name;                             ///< where it came from (path or builtin:...)
    std::vector<Vec3> positions;
    std::vector<std::array<uint32_t, 3>> indices;  ///< one triple per triangle, into positions
    /// Per triangle: non-zero = a mirror (the ray caster's reflections, lighting.h).
    /// Empty (every OBJ file, most built-ins): no mirrors.
    std::vector<uint8_t> mirror;

    size_t triangle_count() const { return indices.size(); }
    Vec3 vertex(size_t tri, int corner) const { return positions[indices[tri][corner]]; }
    Triangle triangle(size_t tri) const {
        return Triangle::from_points(vertex(tri, 0), vertex(tri, 1), vertex(tri, 2));
    }
    TriangleCorners corners(size_t tri) const {
        return TriangleCorners::from_points(vertex(tri, 0), vertex(tri, 1), vertex(tri, 2));
    }
    /// The box structures build around triangle `tri` (triangle_box).
    Aabb triangle_bounds(size_t tri) const { return triangle_box(vertex(tri, 0), vertex(tri, 1), vertex(tri, 2)); }
    /// Bounds of all triangles' boxes (triangle_bounds; empty box for an empty mesh).
    Aabb bounds() const;
    /// Adds a triangle from three points (appends three vertices).
    void add_triangle(Vec3 a, Vec3 b, Vec3 c);
};

/// Triangles of zero area (has_zero_area in triangle.h): their three corners coincide
/// or lie on one line. No ray hits them (Triangle::from_points); they cover no pixel.
size_t count_degenerate_triangles(const Mesh& mesh);

/// The scale the float arithmetic of the ray–triangle test handles exactly enough
/// that the ray caster and the rasterizer agree. Möller–Trumbore's t is a product
/// of three lengths: beyond 1e12 it overflows float (3.4e38), and in a scene less
/// than 1e-12 across it sinks into float's denormals and loses its digits.
inline constexpr double kMaxCoordinate = 1e12;  ///< largest |x|, |y| or |z| of a vertex
inline constexpr double kMinSceneSize = 1e-12;  ///< smallest longest side of the scene's box
/// A point every coordinate of which is finite and within kMaxCoordinate (a light's
/// position, a query point: where a vertex could be).
inline bool within_max_coordinate(Vec3d p) {
    return std::fabs(p.x) <= kMaxCoordinate && std::fabs(p.y) <= kMaxCoordinate && std::fabs(p.z) <= kMaxCoordinate;
}

/// The triangles of a mesh in intersection form: triangles[k] is triangle order[k]
/// (a structure's leaf order, so that a leaf's triangles lie next to each other in
/// memory), or triangle k when `order` is empty. Filled in parallel; `progress` (may be
/// null) advances by one unit per triangle (at ten million references this is seconds).
TriangleArray make_triangles(const Mesh& mesh, std::span<const uint32_t> order = {}, WorkProgress* progress = nullptr);
/// The same into `out`, reusing its memory: a refit copies the moved triangles every frame.
void fill_triangles(const Mesh& mesh, std::span<const uint32_t> order, TriangleArray& out,
                    WorkProgress* progress = nullptr);

/// The same triangles as corners (the watertight test's form): corners[k] is
/// triangle order[k], or triangle k when `order` is empty (a structure's leaf
/// order, so that corners[k] and its triangles[k] are one triangle).
CornerArray make_corners(const Mesh& mesh, std::span<const uint32_t> order = {});

}  // namespace accelviz
