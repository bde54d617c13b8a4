#pragma once
/// Inside or outside a closed mesh, by ray parity (the lecture's list of what a
/// hierarchy answers besides first hits): a ray from the point crosses the surface an
/// odd number of times iff the point is inside. Every crossing must count, not just
/// the first, so the BVH walk here tests every box the ray enters and every triangle
/// in it, without the closest-hit pruning; brute force tests every triangle.
///
/// Robustness: a ray through a shared edge or vertex can count a crossing twice (both
/// triangles accept it: the triangle tests treat their edges as inside) or miss one.
/// Such rays are rare but not impossible, so three rays in fixed directions, none
/// along an axis or a diagonal, vote: the point is inside when at least two of them
/// say so. On a mesh that is not closed the answer has no meaning; the votes then often
/// disagree, and the result says how they fell.

#include <array>
#include <cstdint>

#include "core/accel/bvh.h"
#include "core/geometry/mesh.h"
#include "core/math/box_test.h"
#include "core/traversal/events.h"

namespace accelviz {

/// The three voting directions (unit length).
std::array<Vec3, 3> parity_directions();

struct InsideTest {
    bool inside = false;
    std::array<uint32_t, 3> crossings{};  ///< per direction of parity_directions()
    int votes_inside = 0;                 ///< directions with an odd count
};

/// Events: BoxTest (node, widened interval, hit), VisitNode, Leaf, TriangleTest (tri,
/// t, hit: it counts as a crossing), Done (count = crossings).
template <class Observer>
uint32_t count_crossings_brute_force(const TriangleArray& triangles, const Ray& ray, Observer& obs) {
    uint32_t crossings = 0;
    for (uint32_t tri = 0; tri < triangles.size(); ++tri) {
        const TriangleTest test = intersect_triangle(triangles[tri], ray);
        obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = tri, .t = test.t, .u = test.u, .v = test.v});
        crossings += test.hit ? 1 : 0;
    }
    obs.on({.kind = EventKind::Done, .hit = crossings % 2 == 1, .count = crossings});
    return crossings;
}

/// The same count through `bvh`: a node is skipped only when the ray misses its box
/// (the widened slab test the BVH's traversal uses, so no box holding a hit is missed).
template <class Observer>
uint32_t count_crossings(const Bvh& bvh, const Ray& ray, Observer& obs) {
    uint32_t crossings = 0;
    if (!bvh.nodes.empty()) {
        const BoxTestRay box_ray(ray);
        uint32_t stack[kBvhStackSize];
        int top = 0;
        stack[top++] = 0;
        while (top > 0) {
            const uint32_t index = stack[--top];
            const BvhNode& node = bvh.nodes[index];
            const SlabResult slab = widened_slab_test<false>(node.bounds, box_ray, ray.t_min, ray.t_max);
            obs.on({.kind = EventKind::BoxTest, .hit = slab.hit(), .node = index, .t_enter = slab.t_enter,
                    .t_exit = slab.t_exit});
            if (!slab.hit()) continue;
            obs.on({.kind = EventKind::VisitNode, .node = index, .t_enter = slab.t_enter, .t_exit = slab.t_exit});
            if (node.is_leaf()) {
                obs.on({.kind = EventKind::Leaf, .node = index, .first = node.first, .count = node.count});
                for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                    const TriangleTest test = intersect_triangle(bvh.triangles[k], ray);
                    obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = bvh.prim_ids[k], .t = test.t,
                            .u = test.u, .v = test.v});
                    crossings += test.hit ? 1 : 0;
                }
                continue;
            }
            stack[top++] = node.first + 1;
            stack[top++] = node.first;
        }
    }
    obs.on({.kind = EventKind::Done, .hit = crossings % 2 == 1, .count = crossings});
    return crossings;
}

/// The vote of the three rays from q, each counted by `count(ray)`.
template <class CountCrossings>
InsideTest inside_by_parity(Vec3 q, CountCrossings&& count) {
    InsideTest out;
    const auto directions = parity_directions();
    for (size_t i = 0; i < 3; ++i) {
        out.crossings[i] = count(Ray{q, directions[i], 0.0f, kInfinity});
        out.votes_inside += out.crossings[i] % 2 == 1 ? 1 : 0;
    }
    out.inside = out.votes_inside >= 2;
    return out;
}

}  // namespace accelviz
