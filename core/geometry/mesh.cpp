#include "core/geometry/mesh.h"

namespace accelviz {

Aabb Mesh::bounds() const {
    Aabb b;
    for (size_t t = 0; t < indices.size(); ++t) b.grow(triangle_bounds(t));
    return b;
}

size_t count_degenerate_triangles(const Mesh& mesh) {
    size_t count = 0;
    for (size_t t = 0; t < mesh.triangle_count(); ++t)
        if (has_zero_area(mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2))) ++count;
    return count;
}

void Mesh::add_triangle(Vec3 a, Vec3 b, Vec3 c) {
    const auto base = static_cast<uint32_t>(positions.size());
    positions.push_back(a);
    positions.push_back(b);
    positions.push_back(c);
    indices.push_back({base, base + 1, base + 2});
}

std::vector<Triangle> make_triangles(const Mesh& mesh) {
    std::vector<Triangle> tris(mesh.triangle_count());
    for (size_t i = 0; i < tris.size(); ++i) tris[i] = mesh.triangle(i);
    return tris;
}

}  // namespace accelviz
