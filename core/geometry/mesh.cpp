#include "core/geometry/mesh.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include "core/util/prefetch.h"

namespace accelviz {

// Both passes below run on every load over every triangle (10 million for the
// lecture's big scenes), so they are split across the cores; min, max and counts
// do not depend on the order, so the results are the same on any number of threads.

Aabb Mesh::bounds() const {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, indices.size(), 1 << 16), Aabb{},
        [&](const tbb::blocked_range<size_t>& range, Aabb b) {
            for (size_t t = range.begin(); t < range.end(); ++t) b.grow(triangle_bounds(t));
            return b;
        },
        [](Aabb a, const Aabb& b) { return merge(a, b); });
}

size_t count_degenerate_triangles(const Mesh& mesh) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, mesh.triangle_count(), 1 << 16), size_t(0),
        [&](const tbb::blocked_range<size_t>& range, size_t count) {
            for (size_t t = range.begin(); t < range.end(); ++t)
                if (has_zero_area(mesh.vertex(t, 0), mesh.vertex(t, 1), mesh.vertex(t, 2))) ++count;
            return count;
        },
        [](size_t a, size_t b) { return a + b; });
}

void Mesh::add_triangle(Vec3 a, Vec3 b, Vec3 c) {
    const auto base = static_cast<uint32_t>(positions.size());
    positions.push_back(a);
    positions.push_back(b);
    positions.push_back(c);
    indices.push_back({base, base + 1, base + 2});
}

TriangleArray make_triangles(const Mesh& mesh, std::span<const uint32_t> order, WorkProgress* progress) {
    // Made at its final size with its pages touched by all threads (gigabytes for a big
    // KD tree or octree), then filled.
    TriangleArray tris = make_prefaulted<TriangleArray>(order.empty() ? mesh.triangle_count() : order.size());
    fill_triangles(mesh, order, tris, progress);
    return tris;
}

void fill_triangles(const Mesh& mesh, std::span<const uint32_t> order, TriangleArray& tris, WorkProgress* progress) {
    tris.resize(order.empty() ? mesh.triangle_count() : order.size());
    if (order.empty()) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 1 << 16), [&](const tbb::blocked_range<size_t>& range) {
            for (size_t i = range.begin(); i < range.end(); ++i) tris[i] = mesh.triangle(i);
            advance(progress, range.size());
        });
        return;
    }
    // A leaf order jumps around the mesh, so each triangle's index triple and corners
    // are a cache miss of their own; the loop asks for them some triangles ahead (the
    // triple first, its corners once the triple has had time to arrive) so the misses
    // overlap instead of following each other.
    constexpr size_t kTriplesAhead = 16, kCornersAhead = 8;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, tris.size(), 1 << 14), [&](const tbb::blocked_range<size_t>& range) {
        const size_t end = range.end();
        for (size_t k = range.begin(); k < end; ++k) {
            if (k + kTriplesAhead < end) prefetch(&mesh.indices[order[k + kTriplesAhead]]);
            if (k + kCornersAhead < end)
                for (uint32_t corner : mesh.indices[order[k + kCornersAhead]]) prefetch(&mesh.positions[corner]);
            tris[k] = mesh.triangle(order[k]);
        }
        advance(progress, range.size());
    });
}

CornerArray make_corners(const Mesh& mesh, std::span<const uint32_t> order) {
    CornerArray corners(order.empty() ? mesh.triangle_count() : order.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, corners.size(), 1 << 16), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t k = range.begin(); k < range.end(); ++k) corners[k] = mesh.corners(order.empty() ? k : order[k]);
    });
    return corners;
}

}  // namespace accelviz
