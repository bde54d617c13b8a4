#pragma once
/// The bounding volume hierarchy (lecture: 层次包围盒, BVH) as flat data, and its
/// traversals: algorithm 1 (unordered), algorithm 2 (ordered, early termination)
/// and any-hit. Built by build_bvh() (core/accel/bvh_build.h).
///
/// Exactness: every traversal tests triangles with intersect_triangle() on the
/// same Triangle values make_triangles() gives, keeps the closest by is_closer(),
/// tests boxes with a slab test widened by a few ulps (core/accel/box_test.h) and
/// culls a node only when that widened entry distance is strictly beyond the
/// closest hit; so it returns the same triangle and bit-identical t as BruteForce
/// (except where Möller–Trumbore itself is unreliable: see box_test.h, "Limit").
/// Box events report the widened interval, clipped to the ray's [t_min, t_max].

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/box_test.h"
#include "core/accel/bvh_config.h"
#include "core/geometry/triangle.h"
#include "core/traversal/observers.h"
#include "core/util/large_array.h"
#include "core/util/prefetch.h"

namespace accelviz {

/// One node, 32 bytes (Wald's layout, see STYLE.md).
/// Invariant: a leaf iff count > 0; its triangles are prim_ids[first .. first+count).
/// Otherwise its children are nodes[first] (left) and nodes[first + 1] (right),
/// and both child boxes lie inside `bounds`.
struct BvhNode {
    Aabb bounds;
    uint32_t first = 0;
    uint32_t count = 0;

    bool is_leaf() const { return count > 0; }
};
static_assert(sizeof(BvhNode) == 32, "a BVH node is 32 bytes: two fit in a cache line");

/// The node array's allocator: nodes[1] starts a 64-byte cache line. The root is
/// alone at nodes[0]; every other node has its sibling next to it, pairs starting at
/// odd indices, so each pair fills exactly one line: algorithm 2, which tests both
/// children's boxes of a node, reads one cache line per step instead of often two.
/// (Big arrays also get huge pages: core/util/large_array.h.)
using BvhNodeAllocator = LargeArrayAllocator<BvhNode, sizeof(BvhNode)>;
static_assert(2 * sizeof(BvhNode) == BvhNodeAllocator::kLine, "a sibling pair is one cache line");

/// A BVH over a mesh's triangles.
/// Invariants: nodes[0] is the root (nodes is empty iff there are no triangles);
/// every triangle id appears exactly once in prim_ids, in exactly one leaf;
/// triangles[k] == mesh.triangle(prim_ids[k]) (a copy in leaf order, so a leaf's
/// triangles are contiguous in memory); no leaf is deeper than kBvhMaxDepth.
struct Bvh {
    std::vector<BvhNode, BvhNodeAllocator> nodes;
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> prim_ids;   ///< leaf order → triangle id
    std::vector<Triangle, LargeArrayAllocator<Triangle>> triangles;  ///< leaf order, triangles[k] is triangle prim_ids[k]
    BvhConfig build_config;           ///< what it was built with
    BvhBuildStats build_stats;        ///< what the build produced
    BvhTraversal traversal = BvhTraversal::Ordered;  ///< which closest-hit algorithm intersect_closest runs

    std::string name() const { return "bvh"; }
    nlohmann::json config() const;  ///< build_config + traversal
    nlohmann::json stats() const;   ///< build_stats

    /// Closest hit in [ray.t_min, ray.t_max] by the configured traversal.
    template <class Observer>
    Hit intersect_closest(const Ray& ray, Observer& obs) const {
        return traversal == BvhTraversal::Ordered ? intersect_ordered(ray, obs) : intersect_unordered(ray, obs);
    }

    /// Algorithm 1 (lecture): test the node's box; at a leaf test its triangles;
    /// otherwise visit left, then right. No ordering, no pruning by the closest hit.
    template <class Observer>
    Hit intersect_unordered(const Ray& ray, Observer& obs) const {
        return ray.t_min < 0.0f ? unordered<true>(ray, obs) : unordered<false>(ray, obs);
    }

    /// Algorithm 2 (lecture): at an interior node test both children's boxes and
    /// go to the nearer one first (smaller entry distance; the left on a tie),
    /// keeping the other on the stack; skip every node whose entry distance is
    /// beyond the closest hit found so far.
    template <class Observer>
    Hit intersect_ordered(const Ray& ray, Observer& obs) const {
        return ray.t_min < 0.0f ? ordered<true>(ray, obs) : ordered<false>(ray, obs);
    }

    /// Any hit in [ray.t_min, ray.t_max] (shadow rays): stops at the first one.
    /// Visits children nearest first, like algorithm 2.
    template <class Observer>
    bool intersect_any(const Ray& ray, Observer& obs) const {
        return ray.t_min < 0.0f ? any_hit<true>(ray, obs) : any_hit<false>(ray, obs);
    }
    bool intersect_any(const Ray& ray) const {
        NoObserver obs;
        return intersect_any(ray, obs);
    }

private:
    // The traversals. kMayStartBehind: the ray may hit at t < 0 (t_min < 0), which
    // needs the slower box test (box_test.h); chosen once per ray by the public ones.
    template <bool kMayStartBehind, class Observer>
    Hit unordered(const Ray& ray, Observer& obs) const;
    template <bool kMayStartBehind, class Observer>
    Hit ordered(const Ray& ray, Observer& obs) const;
    template <bool kMayStartBehind, class Observer>
    bool any_hit(const Ray& ray, Observer& obs) const;

    /// Asks the memory system for the children of node `child` (one cache line: the
    /// sibling pair at nodes[first]) while the walk is still testing `child`'s own box:
    /// the next step down waits on that line, and on an 871k-triangle tree it is mostly
    /// not in the caches. Only a hint: nothing changes but when the memory arrives. For a
    /// leaf, `first` counts triangles and the hint falls on some unrelated address,
    /// harmless; choosing the leaf's triangles instead cost more than it saved (measured,
    /// as the hint itself: 871k, one thread, 0.75 -> 0.80x Embree's speed on an AMD EPYC VM).
    void prefetch_children(uint32_t child) const { prefetch_element(nodes.data(), nodes[child].first); }

    /// A node to visit now or later. The walk needs its `first` and `count`, copied
    /// when its box was tested (the same 32 bytes, so going down to its children waits
    /// on no second load of the node), and its box's entry distance (clipped to the
    /// ray). Its id and exit distance only go into events, so they take room only when
    /// an observer watches: the fast path's entries are 12 bytes, not 20. (Measured
    /// against re-reading the node and 20-byte entries: 0.78 -> 0.82x Embree's speed on
    /// the bunny, 0.72 -> 0.75x at 871k.)
    template <bool kWatched>
    struct StackEntry {
        uint32_t first;
        uint32_t count;
        float t_enter;
        [[no_unique_address]] KeptForEvents<uint32_t, kWatched> node;
        [[no_unique_address]] KeptForEvents<float, kWatched> t_exit;

        bool is_leaf() const { return count > 0; }
        /// The entry of node `id` (= n), whose box the ray enters at t_enter and leaves at t_exit.
        static StackEntry of(const BvhNode& n, uint32_t id, float t_enter, float t_exit) {
            return {n.first, n.count, t_enter, id, t_exit};
        }
    };
    static_assert(sizeof(StackEntry<false>) == 12, "unwatched, a stack entry is first, count and t_enter");
    template <class Observer>
    using StackEntryFor = StackEntry<kObserverWatches<Observer>>;
    template <class Observer>
    StackEntryFor<Observer> entry(uint32_t node, float t_enter, float t_exit) const {
        return StackEntryFor<Observer>::of(nodes[node], node, t_enter, t_exit);
    }

    /// Tests the triangles of `leaf` against `ray` (whose t_max is the closest
    /// hit so far, inclusive), updating `best` and `ray.t_max`.
    template <class Observer>
    void intersect_leaf(const StackEntryFor<Observer>& leaf, Ray& ray, Hit& best, Observer& obs) const;

    /// The ray spends time in the box within [t_min, t_max]: the clipped interval is
    /// not empty. (SlabResult::hit() also asks for t_exit >= 0, which is the same for
    /// t_min >= 0 but would skip hits behind the origin for t_min < 0.)
    static bool entered(const SlabResult& box) { return box.t_enter <= box.t_exit; }

    /// A child algorithm 2 skips: it missed the box, or the box starts beyond the closest hit.
    template <class Observer>
    static void cull(uint32_t node, const SlabResult& box, Observer& obs) {
        obs.on({.kind = EventKind::Cull, .reason = entered(box) ? CullReason::BeyondClosestHit : CullReason::MissedBox,
                .node = node, .t_enter = box.t_enter, .t_exit = box.t_exit});
    }

    template <class Observer>
    static Hit done(const Hit& best, Observer& obs) {
        obs.on({.kind = EventKind::Done, .hit = best.found(), .tri = best.tri, .t = best.t, .u = best.u, .v = best.v});
        return best;
    }
};

// ---------------------------------------------------------------------------
// Traversals. Written once each; NoObserver's empty on() makes them the fast path.
// ---------------------------------------------------------------------------

template <class Observer>
[[gnu::always_inline]] inline void Bvh::intersect_leaf(const StackEntryFor<Observer>& leaf, Ray& ray, Hit& best,
                                                       Observer& obs) const {
    obs.on({.kind = EventKind::Leaf, .node = leaf.node, .first = leaf.first, .count = leaf.count,
            .t_enter = leaf.t_enter, .t_exit = leaf.t_exit});
    const uint32_t end = leaf.first + leaf.count;
    for (uint32_t k = leaf.first; k < end; ++k) {
        const TriangleTest test = intersect_triangle(triangles[k], ray);
        obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = prim_ids[k], .t = test.t, .u = test.u,
                .v = test.v});
        if (test.hit && is_closer(test.t, prim_ids[k], best)) {
            best = {prim_ids[k], test.t, test.u, test.v};
            ray.t_max = test.t;  // later triangles must be at least this close (inclusive, as BruteForce)
            obs.on({.kind = EventKind::NewClosest, .tri = best.tri, .t = best.t, .u = best.u, .v = best.v});
        }
    }
}

template <bool kMayStartBehind, class Observer>
Hit Bvh::unordered(const Ray& ray, Observer& obs) const {
    Hit best;
    if (nodes.empty()) return done(best, obs);
    const BoxTestRay box_ray(ray);
    Ray shrinking = ray;  // t_max follows the closest hit, for the triangle tests only
    StackEntry<true> stack[kBvhStackSize];  // always with the id: a popped node's own box is tested next
    StackEntry<true>* top = stack;  // one past the last entry
    uint32_t node = 0;
    while (true) {
        const BvhNode& n = nodes[node];
        // Boxes are tested against the whole ray: algorithm 1 does not prune by the closest hit.
        const SlabResult box = widened_slab_test<kMayStartBehind>(n.bounds, box_ray, ray.t_min, ray.t_max);
        obs.on({.kind = EventKind::BoxTest, .hit = entered(box), .node = node, .t_enter = box.t_enter,
                .t_exit = box.t_exit});
        if (!entered(box)) {
            obs.on({.kind = EventKind::Cull, .reason = CullReason::MissedBox, .node = node, .t_enter = box.t_enter,
                    .t_exit = box.t_exit});
        } else {
            obs.on({.kind = EventKind::VisitNode, .node = node, .t_enter = box.t_enter, .t_exit = box.t_exit});
            if (n.is_leaf()) {
                intersect_leaf(StackEntryFor<Observer>::of(n, node, box.t_enter, box.t_exit), shrinking, best, obs);
            } else {
                // Left now, right later. The right box is not tested yet: the stack
                // entry carries this node's interval, a bound on the child's.
                const uint32_t right = n.first + 1;
                *top++ = StackEntry<true>::of(nodes[right], right, box.t_enter, box.t_exit);
                obs.on({.kind = EventKind::Push, .node = right, .t_enter = box.t_enter, .t_exit = box.t_exit});
                node = n.first;
                continue;
            }
        }
        if (top == stack) break;
        const StackEntry<true> next = *--top;
        obs.on({.kind = EventKind::Pop, .node = next.node, .t_enter = next.t_enter, .t_exit = next.t_exit});
        node = next.node;
    }
    return done(best, obs);
}

template <bool kMayStartBehind, class Observer>
Hit Bvh::ordered(const Ray& ray, Observer& obs) const {
    Hit best;
    if (nodes.empty()) return done(best, obs);
    const BoxTestRay box_ray(ray);
    Ray shrinking = ray;  // t_max follows the closest hit, for the triangle tests
    StackEntryFor<Observer> stack[kBvhStackSize];
    StackEntryFor<Observer>* top = stack;  // one past the last entry

    // The root's box; after this, boxes are tested from the parent, both children at once.
    const SlabResult root = widened_slab_test<kMayStartBehind>(nodes[0].bounds, box_ray, ray.t_min, ray.t_max);
    obs.on({.kind = EventKind::BoxTest, .hit = entered(root), .node = 0, .t_enter = root.t_enter, .t_exit = root.t_exit});
    if (!entered(root)) {
        obs.on({.kind = EventKind::Cull, .reason = CullReason::MissedBox, .node = 0, .t_enter = root.t_enter,
                .t_exit = root.t_exit});
        return done(best, obs);
    }
    StackEntryFor<Observer> current = entry<Observer>(0, root.t_enter, root.t_exit);
    while (true) {
        obs.on({.kind = EventKind::VisitNode, .node = current.node, .t_enter = current.t_enter,
                .t_exit = current.t_exit});
        if (current.is_leaf()) {
            intersect_leaf(current, shrinking, best, obs);
        } else {
            // find_hit_order (lecture): test both children; keep those the ray enters
            // no later than the closest hit so far; go to the nearer, defer the other.
            const uint32_t left = current.first, right = current.first + 1;
            prefetch_children(left);
            prefetch_children(right);
            const SlabResult a = widened_slab_test<kMayStartBehind>(nodes[left].bounds, box_ray, ray.t_min, ray.t_max);
            const SlabResult b = widened_slab_test<kMayStartBehind>(nodes[right].bounds, box_ray, ray.t_min, ray.t_max);
            obs.on({.kind = EventKind::BoxTest, .hit = entered(a), .node = left, .t_enter = a.t_enter, .t_exit = a.t_exit});
            obs.on({.kind = EventKind::BoxTest, .hit = entered(b), .node = right, .t_enter = b.t_enter, .t_exit = b.t_exit});
            const bool keep_left = entered(a) && !(a.t_enter > best.t);
            const bool keep_right = entered(b) && !(b.t_enter > best.t);
            if (!keep_left) cull(left, a, obs);
            if (!keep_right) cull(right, b, obs);
            if (keep_left && keep_right) {
                // Nearer first (the left on a tie); the other waits on the stack with its interval.
                if (b.t_enter < a.t_enter) {
                    *top++ = entry<Observer>(left, a.t_enter, a.t_exit);
                    current = entry<Observer>(right, b.t_enter, b.t_exit);
                } else {
                    *top++ = entry<Observer>(right, b.t_enter, b.t_exit);
                    current = entry<Observer>(left, a.t_enter, a.t_exit);
                }
                const StackEntryFor<Observer>& far = top[-1];
                obs.on({.kind = EventKind::Push, .node = far.node, .t_enter = far.t_enter, .t_exit = far.t_exit});
                continue;
            }
            if (keep_left) {
                current = entry<Observer>(left, a.t_enter, a.t_exit);
                continue;
            }
            if (keep_right) {
                current = entry<Observer>(right, b.t_enter, b.t_exit);
                continue;
            }
        }
        // Next deferred node, skipping those the closest hit has overtaken meanwhile.
        bool found = false;
        while (top != stack) {
            const StackEntryFor<Observer> next = *--top;
            obs.on({.kind = EventKind::Pop, .node = next.node, .t_enter = next.t_enter, .t_exit = next.t_exit});
            if (next.t_enter > best.t) {
                obs.on({.kind = EventKind::Cull, .reason = CullReason::BeyondClosestHit, .node = next.node,
                        .t_enter = next.t_enter, .t_exit = next.t_exit});
                continue;
            }
            current = next;
            found = true;
            break;
        }
        if (!found) break;
    }
    return done(best, obs);
}

template <bool kMayStartBehind, class Observer>
bool Bvh::any_hit(const Ray& ray, Observer& obs) const {
    auto finish = [&](const Hit& hit) {
        obs.on({.kind = EventKind::Done, .hit = hit.found(), .tri = hit.tri, .t = hit.t, .u = hit.u, .v = hit.v});
        return hit.found();
    };
    if (nodes.empty()) return finish(Hit{});
    const BoxTestRay box_ray(ray);
    StackEntryFor<Observer> stack[kBvhStackSize];
    StackEntryFor<Observer>* top = stack;  // one past the last entry
    const SlabResult root = widened_slab_test<kMayStartBehind>(nodes[0].bounds, box_ray, ray.t_min, ray.t_max);
    obs.on({.kind = EventKind::BoxTest, .hit = entered(root), .node = 0, .t_enter = root.t_enter, .t_exit = root.t_exit});
    if (!entered(root)) {
        obs.on({.kind = EventKind::Cull, .reason = CullReason::MissedBox, .node = 0, .t_enter = root.t_enter,
                .t_exit = root.t_exit});
        return finish(Hit{});
    }
    StackEntryFor<Observer> current = entry<Observer>(0, root.t_enter, root.t_exit);
    while (true) {
        obs.on({.kind = EventKind::VisitNode, .node = current.node, .t_enter = current.t_enter,
                .t_exit = current.t_exit});
        if (current.is_leaf()) {
            obs.on({.kind = EventKind::Leaf, .node = current.node, .first = current.first, .count = current.count,
                    .t_enter = current.t_enter, .t_exit = current.t_exit});
            for (uint32_t k = current.first; k < current.first + current.count; ++k) {
                const TriangleTest test = intersect_triangle(triangles[k], ray);
                obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = prim_ids[k], .t = test.t,
                        .u = test.u, .v = test.v});
                if (test.hit) return finish(Hit{prim_ids[k], test.t, test.u, test.v});
            }
        } else {
            StackEntryFor<Observer> child[2];
            bool keep[2];
            prefetch_children(current.first);
            prefetch_children(current.first + 1);
            for (int side = 0; side < 2; ++side) {
                const uint32_t id = current.first + uint32_t(side);
                const SlabResult box = widened_slab_test<kMayStartBehind>(nodes[id].bounds, box_ray, ray.t_min, ray.t_max);
                obs.on({.kind = EventKind::BoxTest, .hit = entered(box), .node = id, .t_enter = box.t_enter,
                        .t_exit = box.t_exit});
                child[side] = entry<Observer>(id, box.t_enter, box.t_exit);
                keep[side] = entered(box);
                if (!keep[side])
                    obs.on({.kind = EventKind::Cull, .reason = CullReason::MissedBox, .node = id,
                            .t_enter = box.t_enter, .t_exit = box.t_exit});
            }
            if (keep[0] && keep[1]) {
                const bool right_first = child[1].t_enter < child[0].t_enter;
                const StackEntryFor<Observer>& far = child[right_first ? 0 : 1];
                *top++ = far;
                obs.on({.kind = EventKind::Push, .node = far.node, .t_enter = far.t_enter, .t_exit = far.t_exit});
                current = child[right_first ? 1 : 0];
                continue;
            }
            if (keep[0] || keep[1]) {
                current = child[keep[0] ? 0 : 1];
                continue;
            }
        }
        if (top == stack) break;
        current = *--top;
        obs.on({.kind = EventKind::Pop, .node = current.node, .t_enter = current.t_enter, .t_exit = current.t_exit});
    }
    return finish(Hit{});
}

// The traversals for the three observers every structure serves are compiled once, in
// bvh.cpp: a file with little else in it, so the compiler inlines the box and triangle
// tests into the loop (in a file holding many structures it may run out of its
// inlining budget and call them, which costs a third of the speed).
#define ACCELVIZ_BVH_TRAVERSALS(EXTERN, OBSERVER)                                    \
    EXTERN template Hit Bvh::ordered<false>(const Ray&, OBSERVER&) const;            \
    EXTERN template Hit Bvh::ordered<true>(const Ray&, OBSERVER&) const;             \
    EXTERN template Hit Bvh::unordered<false>(const Ray&, OBSERVER&) const;          \
    EXTERN template Hit Bvh::unordered<true>(const Ray&, OBSERVER&) const;           \
    EXTERN template bool Bvh::any_hit<false>(const Ray&, OBSERVER&) const;           \
    EXTERN template bool Bvh::any_hit<true>(const Ray&, OBSERVER&) const;
ACCELVIZ_BVH_TRAVERSALS(extern, NoObserver)
ACCELVIZ_BVH_TRAVERSALS(extern, CountingObserver)
ACCELVIZ_BVH_TRAVERSALS(extern, RecordingObserver)

}  // namespace accelviz
