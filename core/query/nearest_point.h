#pragma once
/// The closest-point query (lecture: the hierarchy answers more than rays, e.g. the
/// point on the mesh nearest to a given point), through brute force, the BVH and the
/// KD tree. Each is one traversal templated on an observer, like the ray queries, so
/// the events a stepper would replay and the counts come from the code that answers.
///
/// Exactness: every version measures a triangle with the same function on the same
/// float corners (the mesh's), in double, keeps the nearest by is_nearer() (distance,
/// then the lower triangle id), and skips a node only when its box is farther than the
/// best distance (with a relative slack, kPruneSlack). The nearest point computed is
/// clamped into the corners' box: rounding can put it a little outside (3e-18 beyond
/// a face at x = 0 on the teapot), where it would be nearer than the boxes around the
/// triangle. Inside the corners' box, and so inside every node box above the triangle,
/// its distance to q is at least the box's, coordinate by coordinate in the same
/// rounded arithmetic; the box's distance is a lower bound of every triangle's below
/// it, and the answer is brute force's, bit for bit.
///
/// Events: Push (node, t_enter = its box's distance: it waits on the stack), Pop (node,
/// taken off), VisitNode (node), Cull (node, reason BeyondClosestHit, t_enter = the
/// box's distance), Leaf (node, first, count), TriangleTest (tri, t = its distance, hit
/// = it is the nearest so far), NewClosest (tri, t), Done (tri, t, hit = found). The
/// t of every event is a distance from the query point, not a ray parameter.

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/accel/accelerator.h"
#include "core/accel/bvh.h"
#include "core/accel/kd_tree.h"
#include "core/geometry/mesh.h"
#include "core/traversal/events.h"

namespace accelviz {

struct NearestPoint {
    uint32_t tri = Hit::kNoHit;
    double distance_squared = std::numeric_limits<double>::infinity();
    Vec3d point;  ///< the nearest point on triangle `tri`

    bool found() const { return tri != Hit::kNoHit; }
    double distance() const { return std::sqrt(distance_squared); }
};

/// The point of triangle (a, b, c) nearest to p: its projection onto the plane when
/// it falls inside the triangle, else the nearest point of the three edges (the
/// regions of Ericson, Real-Time Collision Detection, 2005, section 5.1.5, told apart
/// by tests that stay exact enough on slivers). Degenerate triangles (a segment or a
/// point) give a point of the segment or the point.
Vec3d closest_point_on_triangle(Vec3d p, Vec3d a, Vec3d b, Vec3d c);

/// Squared distance from p to the nearest point of `box` (0 inside).
double box_distance_squared(Vec3d p, const Aabb& box);

/// A node is skipped when its box's squared distance exceeds the best by this factor:
/// the box's and the triangle's distances are each rounded (double, relative error
/// about 1e-15), so a box closer than the best in exact arithmetic is never skipped.
inline constexpr double kPruneSlack = 1.0 + 1e-9;

/// Triangle `tri` of `mesh` measured from q: the nearest point and its squared distance.
inline NearestPoint measure_triangle(const Mesh& mesh, uint32_t tri, Vec3d q) {
    NearestPoint m;
    m.tri = tri;
    const Vec3 a = mesh.vertex(tri, 0), b = mesh.vertex(tri, 1), c = mesh.vertex(tri, 2);
    m.point = closest_point_on_triangle(q, to_double(a), to_double(b), to_double(c));
    // Into the corners' box (see "Exactness" above).
    m.point.x = std::clamp(m.point.x, double(std::min({a.x, b.x, c.x})), double(std::max({a.x, b.x, c.x})));
    m.point.y = std::clamp(m.point.y, double(std::min({a.y, b.y, c.y})), double(std::max({a.y, b.y, c.y})));
    m.point.z = std::clamp(m.point.z, double(std::min({a.z, b.z, c.z})), double(std::max({a.z, b.z, c.z})));
    const Vec3d d = m.point - q;
    m.distance_squared = dot(d, d);
    return m;
}

/// The order every version keeps: nearer, or as near with a lower triangle id.
inline bool is_nearer(const NearestPoint& candidate, const NearestPoint& best) {
    return candidate.distance_squared < best.distance_squared ||
           (candidate.distance_squared == best.distance_squared && candidate.tri < best.tri);
}

namespace nearest_detail {

/// Tests one triangle, reports it, and keeps it if it is the nearest so far.
template <class Observer>
void test_triangle(const Mesh& mesh, uint32_t tri, Vec3d q, NearestPoint& best, Observer& obs) {
    const NearestPoint m = measure_triangle(mesh, tri, q);
    const bool nearer = is_nearer(m, best);
    obs.on({.kind = EventKind::TriangleTest, .hit = nearer, .tri = tri, .t = float(std::sqrt(m.distance_squared))});
    if (!nearer) return;
    best = m;
    obs.on({.kind = EventKind::NewClosest, .tri = tri, .t = float(best.distance())});
}

template <class Observer>
NearestPoint done(const NearestPoint& best, Observer& obs) {
    obs.on({.kind = EventKind::Done, .hit = best.found(), .tri = best.tri,
            .t = best.found() ? float(best.distance()) : kInfinity});
    return best;
}

/// Whether a box at squared distance `d2` may hold something as near as `best`.
inline bool may_hold_nearer(double d2, const NearestPoint& best) {
    return !(d2 > best.distance_squared * kPruneSlack);
}

/// A node taken off a search's stack, its box `d2` from q: skipped (with its subtree)
/// when farther than the best so far, else visited; a leaf's triangles,
/// prim_ids[first .. first + count), are measured. True: an interior node was
/// visited, and the caller pushes its children.
template <class Observer>
bool enter_node(uint32_t node, double d2, bool leaf, uint32_t first, uint32_t count, const uint32_t* prim_ids,
                const Mesh& mesh, Vec3d q, NearestPoint& best, Observer& obs) {
    if (!may_hold_nearer(d2, best)) {
        obs.on({.kind = EventKind::Cull, .reason = CullReason::BeyondClosestHit, .node = node,
                .t_enter = float(std::sqrt(d2))});
        return false;
    }
    obs.on({.kind = EventKind::VisitNode, .node = node, .t_enter = float(std::sqrt(d2))});
    if (!leaf) return true;
    obs.on({.kind = EventKind::Leaf, .node = node, .first = first, .count = count});
    for (uint32_t k = first; k < first + count; ++k) test_triangle(mesh, prim_ids[k], q, best, obs);
    return false;
}

}  // namespace nearest_detail

/// Every triangle, in id order: the oracle.
template <class Observer>
NearestPoint nearest_point_brute_force(const Mesh& mesh, Vec3d q, Observer& obs) {
    NearestPoint best;
    for (uint32_t tri = 0; tri < mesh.triangle_count(); ++tri) nearest_detail::test_triangle(mesh, tri, q, best, obs);
    return nearest_detail::done(best, obs);
}

/// Through `bvh` (built over `mesh`): the nearer child first; a node whose box is
/// farther than the best so far is skipped with its subtree (the lecture's early
/// termination, with the box's distance in place of the ray's entry distance).
template <class Observer>
NearestPoint nearest_point(const Bvh& bvh, const Mesh& mesh, Vec3d q, Observer& obs) {
    NearestPoint best;
    if (bvh.nodes.empty()) return nearest_detail::done(best, obs);
    struct Entry {
        uint32_t node;
        double d2;
    };
    Entry stack[kBvhStackSize];
    int top = 0;
    auto push = [&](Entry e) {
        obs.on({.kind = EventKind::Push, .node = e.node, .t_enter = float(std::sqrt(e.d2))});
        stack[top++] = e;
    };
    push({0, box_distance_squared(q, bvh.nodes[0].bounds)});
    while (top > 0) {
        const Entry e = stack[--top];
        obs.on({.kind = EventKind::Pop, .node = e.node, .t_enter = float(std::sqrt(e.d2))});
        const BvhNode& node = bvh.nodes[e.node];
        if (!nearest_detail::enter_node(e.node, e.d2, node.is_leaf(), node.first, node.count, bvh.prim_ids.data(),
                                        mesh, q, best, obs))
            continue;
        // Both children's distances; the farther is pushed first, so the nearer is next.
        Entry a{node.first, box_distance_squared(q, bvh.nodes[node.first].bounds)};
        Entry b{node.first + 1, box_distance_squared(q, bvh.nodes[node.first + 1].bounds)};
        if (b.d2 < a.d2) std::swap(a, b);
        push(b);
        push(a);
    }
    return nearest_detail::done(best, obs);
}

/// Through `kd` (built over `mesh`): the cell holding q's side of each plane first; the
/// far cell only if its box is no farther than the best so far. A triangle in several
/// cells is measured in each it is met in (the same distance each time).
template <class Observer>
NearestPoint nearest_point(const KdTree& kd, const Mesh& mesh, Vec3d q, Observer& obs) {
    NearestPoint best;
    if (kd.nodes.empty()) return nearest_detail::done(best, obs);
    struct Entry {
        uint32_t node;
        Aabb box;
        double d2;
    };
    std::vector<Entry> stack;
    auto push = [&](const Entry& e) {
        obs.on({.kind = EventKind::Push, .node = e.node, .t_enter = float(std::sqrt(e.d2))});
        stack.push_back(e);
    };
    push({0, kd.bounds, box_distance_squared(q, kd.bounds)});
    while (!stack.empty()) {
        const Entry e = stack.back();
        stack.pop_back();
        obs.on({.kind = EventKind::Pop, .node = e.node, .t_enter = float(std::sqrt(e.d2))});
        const KdNode& node = kd.nodes[e.node];
        if (!nearest_detail::enter_node(e.node, e.d2, node.is_leaf(), node.first(), node.count(), kd.prim_ids.data(), mesh,
                                        q, best, obs))
            continue;
        Aabb lower = e.box, upper = e.box;
        lower.hi[node.axis()] = node.split();
        upper.lo[node.axis()] = node.split();
        Entry near{node.lower_child(), lower, box_distance_squared(q, lower)};
        Entry far{node.upper_child(), upper, box_distance_squared(q, upper)};
        if (double(node.split()) < (node.axis() == 0 ? q.x : node.axis() == 1 ? q.y : q.z)) std::swap(near, far);
        push(far);
        push(near);
    }
    return nearest_detail::done(best, obs);
}

/// Whether `accel` has a nearest-point search: naive (brute force), the binary BVH or
/// the KD tree. The other structures answer rays only.
inline bool has_nearest_search(const Accelerator& accel) {
    return accel.type() == AccelType::Naive || structure_if<Bvh>(accel) != nullptr ||
           structure_if<KdTree>(accel) != nullptr;
}

/// The nearest point through whichever structure `accel` is (has_nearest_search());
/// brute force for any other.
template <class Observer>
NearestPoint nearest_point(const Accelerator& accel, const Mesh& mesh, Vec3d q, Observer& obs) {
    if (const Bvh* bvh = structure_if<Bvh>(accel)) return nearest_point(*bvh, mesh, q, obs);
    if (const KdTree* kd = structure_if<KdTree>(accel)) return nearest_point(*kd, mesh, q, obs);
    return nearest_point_brute_force(mesh, q, obs);
}

}  // namespace accelviz
