#pragma once
/// The bounding volume hierarchy (lecture: 层次包围盒, BVH) as flat data, and its
/// traversal: one walk with the lecture's two switches, the order of the children
/// (algorithm 1: left then right; algorithm 2: nearest first, with early
/// termination) and when to stop (the closest hit, or any hit for shadow rays).
/// Built by build_bvh() (core/accel/bvh_build.h).
///
/// Exactness: every traversal tests triangles with intersect_triangle() on the
/// same Triangle values make_triangles() gives, keeps the closest by is_closer(),
/// tests boxes with a slab test widened by a few ulps (core/math/box_test.h) and
/// culls a node only when that widened entry distance is strictly beyond the
/// closest hit; so it returns the same triangle and bit-identical t as BruteForce.
/// (The triangle test keeps every hit inside its triangle's widened box, so no
/// node holding the hit is culled before it is found: core/geometry/triangle.h.)
/// Box events report the widened interval, clipped to the ray's [t_min, t_max].

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/accel_type.h"
#include "core/math/box_pair_test.h"
#include "core/math/box_test.h"
#include "core/accel/bvh_config.h"
#include "core/geometry/triangle.h"
#include "core/traversal/observers.h"
#include "core/util/large_array.h"
#include "core/util/prefetch.h"

namespace accelviz {

/// One node, 32 bytes (Wald's layout: two fit in a cache line).
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
static_assert(offsetof(BvhNode, bounds) == 0, "the pair box test reads a node's 32 bytes from its box");

/// The node array's allocator: nodes[1] starts a 64-byte cache line. The root is
/// alone at nodes[0]; every other node has its sibling next to it, pairs starting at
/// odd indices, so each pair fills exactly one line: algorithm 2, which tests both
/// children's boxes of a node, reads one cache line per step instead of often two.
/// (Big arrays also get huge pages: core/util/large_array.h.)
using BvhNodeAllocator = LargeArrayAllocator<BvhNode, sizeof(BvhNode)>;
static_assert(2 * sizeof(BvhNode) == BvhNodeAllocator::kLine, "a sibling pair is one cache line");

/// The two switches of the lecture's find_closest_hit, which make its two
/// algorithms (and the shadow ray's any-hit query) one traversal: ChildOrder, and
/// StopAt (observers.h).
enum class ChildOrder {
    LeftThenRight,  ///< algorithm 1: left child, then right; each box tested on arrival
    NearestFirst,   ///< algorithm 2: both children's boxes tested, the nearer visited first
};

/// A BVH over a mesh's triangles.
/// Invariants: nodes[0] is the root (nodes is empty iff there are no triangles);
/// every triangle id appears exactly once in prim_ids, in exactly one leaf;
/// triangles[k] == mesh.triangle(prim_ids[k]) (a copy in leaf order, so a leaf's
/// triangles are contiguous in memory); no leaf is deeper than kBvhMaxDepth.
struct Bvh {
    std::vector<BvhNode, BvhNodeAllocator> nodes;
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> prim_ids;   ///< leaf order → triangle id
    TriangleArray triangles;  ///< leaf order, triangles[k] is triangle prim_ids[k]
    CornerArray corners;      ///< the same, as corners; only when triangle_test is watertight
    BvhConfig build_config;           ///< what it was built with
    BvhBuildStats build_stats;        ///< what the build produced
    BvhTraversal traversal = BvhTraversal::Ordered;  ///< which closest-hit algorithm intersect_closest runs
    TriangleTestKind triangle_test = TriangleTestKind::MollerTrumbore;  ///< which ray-triangle test the leaves run

    static constexpr AccelType kType = AccelType::Bvh;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const;  ///< build_config + traversal + triangle_test
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
        return traverse<ChildOrder::LeftThenRight, StopAt::ClosestHit>(ray, obs);
    }

    /// Algorithm 2 (lecture): at an interior node test both children's boxes and
    /// go to the nearer one first (smaller entry distance; the left on a tie),
    /// keeping the other on the stack; skip every node whose entry distance is
    /// beyond the closest hit found so far.
    template <class Observer>
    Hit intersect_ordered(const Ray& ray, Observer& obs) const {
        return traverse<ChildOrder::NearestFirst, StopAt::ClosestHit>(ray, obs);
    }

    /// Any hit in [ray.t_min, ray.t_max] (shadow rays): stops at the first one.
    /// Visits children nearest first, like algorithm 2.
    template <class Observer>
    bool intersect_any(const Ray& ray, Observer& obs) const {
        return traverse<ChildOrder::NearestFirst, StopAt::AnyHit>(ray, obs).found();
    }
    bool intersect_any(const Ray& ray) const {
        NoObserver obs;
        return intersect_any(ray, obs);
    }

    /// The one traversal. A ray that may hit at t < 0 (t_min < 0) needs the slower
    /// box test (box_test.h): chosen here once per ray.
    /// So is the triangle test (the one in `triangle_test`).
    template <ChildOrder kOrder, StopAt kStop, class Observer>
    Hit traverse(const Ray& ray, Observer& obs) const {
        if (triangle_test == TriangleTestKind::Watertight)
            return ray.t_min < 0.0f ? walk<kOrder, kStop, true, TriangleTestKind::Watertight>(ray, obs)
                                    : walk<kOrder, kStop, false, TriangleTestKind::Watertight>(ray, obs);
        return ray.t_min < 0.0f ? walk<kOrder, kStop, true, TriangleTestKind::MollerTrumbore>(ray, obs)
                                : walk<kOrder, kStop, false, TriangleTestKind::MollerTrumbore>(ray, obs);
    }

private:
    template <ChildOrder kOrder, StopAt kStop, bool kMayStartBehind, TriangleTestKind kTest, class Observer>
    Hit walk(const Ray& ray, Observer& obs) const;

    /// Asks the memory system for the children of node `child` (one cache line: the
    /// sibling pair at nodes[first]) while the walk is still testing `child`'s own box:
    /// the next step down waits on that line, which in a large tree is mostly not in
    /// the caches. Only a hint: nothing changes but when the memory arrives. For a
    /// leaf, `first` counts triangles and the hint falls on some unrelated address,
    /// which is harmless.
    void prefetch_children(uint32_t child) const { prefetch_element(nodes.data(), nodes[child].first); }

    /// A node to visit now or later. The walk needs its `first` and `count`, copied
    /// when its box was tested (the same 32 bytes, so going down to its children waits
    /// on no second load of the node), and its box's entry distance (clipped to the
    /// ray). Its id and exit distance are needed only by events and by algorithm 1
    /// (which tests a deferred node's box when it gets there), so otherwise they take
    /// no room: the fast path's entries are 12 bytes, not 20.
    template <bool kKeepsId>
    struct StackEntry {
        uint32_t first;
        uint32_t count;
        float t_enter;
        [[no_unique_address]] KeptForEvents<uint32_t, kKeepsId> node;
        [[no_unique_address]] KeptForEvents<float, kKeepsId> t_exit;

        bool is_leaf() const { return count > 0; }
        /// The entry of node `id` (= n), whose box the ray enters at t_enter and leaves at t_exit.
        static StackEntry of(const BvhNode& n, uint32_t id, float t_enter, float t_exit) {
            return {n.first, n.count, t_enter, id, t_exit};
        }
    };
    static_assert(sizeof(StackEntry<false>) == 12, "without the id, a stack entry is first, count and t_enter");

    /// Tests node `node`'s box against the whole ray and reports it.
    template <bool kMayStartBehind, class Observer>
    [[gnu::always_inline]] SlabResult test_box(uint32_t node, const BoxTestRay& box_ray, const Ray& ray, Observer& obs) const {
        const SlabResult box = widened_slab_test<kMayStartBehind>(nodes[node].bounds, box_ray, ray.t_min, ray.t_max);
        obs.on({.kind = EventKind::BoxTest, .hit = entered(box), .node = node, .t_enter = box.t_enter,
                .t_exit = box.t_exit});
        return box;
    }

    /// Tests the boxes of the sibling pair nodes[left], nodes[left + 1] with one
    /// instruction sequence (box_pair_test.h) and reports them, left then right; kept:
    /// those the ray enters no later than `limit`.
    template <bool kMayStartBehind, class Observer>
    [[gnu::always_inline]] SlabPair test_boxes(uint32_t left, const BoxPairTestRay<kMayStartBehind>& pair_ray,
                                               const Ray& ray, float limit, Observer& obs) const {
        const SlabPair pair =
            widened_slab_test_pair(nodes[left].bounds, nodes[left + 1].bounds, pair_ray, ray.t_min, ray.t_max, limit);
        for (uint32_t i = 0; i < 2; ++i)
            obs.on({.kind = EventKind::BoxTest, .hit = entered(pair.boxes[i]), .node = left + i,
                    .t_enter = pair.boxes[i].t_enter, .t_exit = pair.boxes[i].t_exit});
        return pair;
    }

    /// Reports `leaf` and tests its triangles (intersect_leaf_triangles, below).
    template <StopAt kStop, class Entry, class Tester, class Observer>
    bool intersect_leaf(const Entry& leaf, Ray& ray, const Tester& tester, Hit& best, Observer& obs) const;

    /// The ray spends time in the box within [t_min, t_max]: the clipped interval is
    /// not empty. (SlabResult::hit() also asks for t_exit >= 0, which is the same for
    /// t_min >= 0 but would skip hits behind the origin for t_min < 0.)
    static bool entered(const SlabResult& box) { return box.t_enter <= box.t_exit; }

    /// A node the walk skips: it missed the box, or the box starts beyond the closest hit.
    template <class Observer>
    static void cull(uint32_t node, const SlabResult& box, Observer& obs) {
        obs.on({.kind = EventKind::Cull, .reason = entered(box) ? CullReason::BeyondClosestHit : CullReason::MissedBox,
                .node = node, .t_enter = box.t_enter, .t_exit = box.t_exit});
    }
};

// ---------------------------------------------------------------------------
// The traversal. Written once; NoObserver's empty on() makes it the fast path.
// ---------------------------------------------------------------------------

/// What a BVH leaf does with the test of triangle `id` against `ray` (whose t_max is
/// the closest hit so far, inclusive): reports it, and keeps a hit that is closer in
/// `best` and `ray.t_max`. Any-hit: true at the first hit (in `best`), which ends the walk.
template <StopAt kStop, class Observer>
[[gnu::always_inline]] inline bool take_triangle_test(const TriangleTest& test, uint32_t id, Ray& ray, Hit& best,
                                                      Observer& obs) {
    obs.on({.kind = EventKind::TriangleTest, .hit = test.hit, .tri = id, .t = test.t, .u = test.u, .v = test.v});
    if constexpr (kStop == StopAt::AnyHit) {
        if (test.hit) {
            best = {id, test.t, test.u, test.v};
            return true;
        }
    } else if (test.hit && is_closer(test.t, id, best)) {
        best = {id, test.t, test.u, test.v};
        ray.t_max = test.t;  // later triangles must be at least this close (inclusive, as BruteForce)
        obs.on({.kind = EventKind::NewClosest, .tri = best.tri, .t = best.t, .u = best.u, .v = best.v});
    }
    return false;
}

/// Tests the triangles [first, first + count) of a leaf-ordered triangle array one by
/// one (take_triangle_test); prim_ids[k] is the id of triangle k. The binary BVH's
/// leaves run this, and the wide BVH's with the watertight test (with Möller–Trumbore
/// its leaves are lanes: intersect_leaf_lanes in wide_bvh.h).
template <StopAt kStop, class Tester, class Observer>
[[gnu::always_inline]] inline bool intersect_leaf_triangles(uint32_t first, uint32_t count, const uint32_t* prim_ids,
                                                           Ray& ray, const Tester& tester, Hit& best, Observer& obs) {
    for (uint32_t k = first; k < first + count; ++k)
        if (take_triangle_test<kStop>(tester.test(k, ray), prim_ids[k], ray, best, obs)) return true;
    return false;
}

template <StopAt kStop, class Entry, class Tester, class Observer>
[[gnu::always_inline]] inline bool Bvh::intersect_leaf(const Entry& leaf, Ray& ray, const Tester& tester,
                                                      Hit& best, Observer& obs) const {
    obs.on({.kind = EventKind::Leaf, .node = leaf.node, .first = leaf.first, .count = leaf.count,
            .t_enter = leaf.t_enter, .t_exit = leaf.t_exit});
    return intersect_leaf_triangles<kStop>(leaf.first, leaf.count, prim_ids.data(), ray, tester, best, obs);
}

template <ChildOrder kOrder, StopAt kStop, bool kMayStartBehind, TriangleTestKind kTest, class Observer>
Hit Bvh::walk(const Ray& ray, Observer& obs) const {
    constexpr bool kNearestFirst = kOrder == ChildOrder::NearestFirst;
    constexpr bool kClosest = kStop == StopAt::ClosestHit;
    using Entry = StackEntry<kObserverWatches<Observer> || !kNearestFirst>;
    Hit best;
    if (nodes.empty()) return report_done(best, obs);
    const TriangleTester<kTest> tester(ray, triangles, corners);
    const BoxTestRay& box_ray = tester.box_ray();
    const BoxPairTestRay<kMayStartBehind> pair_ray(box_ray);
    Ray shrinking = ray;  // t_max follows the closest hit, for the triangle tests only
    Entry stack[kBvhStackSize];
    Entry* top = stack;  // one past the last entry

    // The root's box (lecture: a ray that misses the bounding box misses every triangle).
    const SlabResult root = test_box<kMayStartBehind>(0, box_ray, ray, obs);
    if (!entered(root)) {
        cull(0, root, obs);
        return report_done(best, obs);
    }
    Entry current = Entry::of(nodes[0], 0, root.t_enter, root.t_exit);
    while (true) {
        obs.on({.kind = EventKind::VisitNode, .node = current.node, .t_enter = current.t_enter,
                .t_exit = current.t_exit});
        if (current.is_leaf()) {
            if (intersect_leaf<kStop>(current, shrinking, tester, best, obs)) return report_done(best, obs);
        } else if constexpr (kNearestFirst) {
            // find_hit_order (lecture): test both children; keep those the ray enters
            // no later than the closest hit so far; go to the nearer, defer the other.
            const uint32_t left = current.first, right = current.first + 1;
            prefetch_children(left);
            prefetch_children(right);
            const SlabPair pair = test_boxes(left, pair_ray, ray, kClosest ? best.t : kInfinity, obs);
            const SlabResult &a = pair.boxes[0], &b = pair.boxes[1];
            const bool keep_left = pair.kept & 1, keep_right = pair.kept >> 1;
            if (!keep_left) cull(left, a, obs);
            if (!keep_right) cull(right, b, obs);
            if (keep_left && keep_right) {
                // Nearer first (the left on a tie); the other waits on the stack with its interval.
                if (b.t_enter < a.t_enter) {
                    *top++ = Entry::of(nodes[left], left, a.t_enter, a.t_exit);
                    current = Entry::of(nodes[right], right, b.t_enter, b.t_exit);
                } else {
                    *top++ = Entry::of(nodes[right], right, b.t_enter, b.t_exit);
                    current = Entry::of(nodes[left], left, a.t_enter, a.t_exit);
                }
                const Entry& far = top[-1];
                obs.on({.kind = EventKind::Push, .node = far.node, .t_enter = far.t_enter, .t_exit = far.t_exit});
                continue;
            }
            if (keep_left) {
                current = Entry::of(nodes[left], left, a.t_enter, a.t_exit);
                continue;
            }
            if (keep_right) {
                current = Entry::of(nodes[right], right, b.t_enter, b.t_exit);
                continue;
            }
        } else {
            // Left now, right later. The right box is not tested yet: the stack entry
            // carries this node's interval, a bound on the child's.
            const uint32_t left = current.first, right = current.first + 1;
            *top++ = Entry::of(nodes[right], right, current.t_enter, current.t_exit);
            obs.on({.kind = EventKind::Push, .node = right, .t_enter = current.t_enter, .t_exit = current.t_exit});
            const SlabResult a = test_box<kMayStartBehind>(left, box_ray, ray, obs);
            if (entered(a)) {
                current = Entry::of(nodes[left], left, a.t_enter, a.t_exit);
                continue;
            }
            cull(left, a, obs);
        }
        // The next deferred node: algorithm 1 tests its box now; algorithm 2 skips it
        // if the closest hit has overtaken it meanwhile.
        bool found = false;
        while (top != stack) {
            Entry next = *--top;
            obs.on({.kind = EventKind::Pop, .node = next.node, .t_enter = next.t_enter, .t_exit = next.t_exit});
            if constexpr (!kNearestFirst) {
                const SlabResult box = test_box<kMayStartBehind>(next.node, box_ray, ray, obs);
                if (!entered(box)) {
                    cull(next.node, box, obs);
                    continue;
                }
                next.t_enter = box.t_enter;
                next.t_exit = box.t_exit;
            } else if constexpr (kClosest) {
                if (next.t_enter > best.t) {
                    obs.on({.kind = EventKind::Cull, .reason = CullReason::BeyondClosestHit, .node = next.node,
                            .t_enter = next.t_enter, .t_exit = next.t_exit});
                    continue;
                }
            }
            current = next;
            found = true;
            break;
        }
        if (!found) break;
    }
    return report_done(best, obs);
}

// The traversals for the three observers every structure serves are compiled once, in
// bvh.cpp (Möller–Trumbore) and bvh_watertight.cpp: files with little else in them, so
// the compiler inlines the box and triangle tests into the loop (in a file holding
// many structures, or both tests' walks, it may run out of its inlining budget and
// call them, which costs a tenth to a third of the speed).
#define ACCELVIZ_BVH_WALK(EXTERN, ORDER, STOP, BEHIND, TEST, OBSERVER) \
    EXTERN template Hit Bvh::walk<ChildOrder::ORDER, StopAt::STOP, BEHIND, TriangleTestKind::TEST>(const Ray&, OBSERVER&) const;
#define ACCELVIZ_BVH_WALKS(EXTERN, TEST, OBSERVER)                        \
    ACCELVIZ_BVH_WALK(EXTERN, NearestFirst, ClosestHit, false, TEST, OBSERVER)  \
    ACCELVIZ_BVH_WALK(EXTERN, NearestFirst, ClosestHit, true, TEST, OBSERVER)   \
    ACCELVIZ_BVH_WALK(EXTERN, LeftThenRight, ClosestHit, false, TEST, OBSERVER) \
    ACCELVIZ_BVH_WALK(EXTERN, LeftThenRight, ClosestHit, true, TEST, OBSERVER)  \
    ACCELVIZ_BVH_WALK(EXTERN, NearestFirst, AnyHit, false, TEST, OBSERVER)      \
    ACCELVIZ_BVH_WALK(EXTERN, NearestFirst, AnyHit, true, TEST, OBSERVER)
#define ACCELVIZ_BVH_TRAVERSALS(EXTERN, TEST)          \
    ACCELVIZ_BVH_WALKS(EXTERN, TEST, NoObserver)       \
    ACCELVIZ_BVH_WALKS(EXTERN, TEST, CountingObserver) \
    ACCELVIZ_BVH_WALKS(EXTERN, TEST, RecordingObserver)
ACCELVIZ_BVH_TRAVERSALS(extern, MollerTrumbore)
ACCELVIZ_BVH_TRAVERSALS(extern, Watertight)

}  // namespace accelviz
