#pragma once
/// The wide BVH: the lecture's binary tree with levels pulled together, so that a
/// node holds up to W = 4 or 8 children whose boxes are tested by one SIMD
/// instruction sequence (core/math/box_lanes.h). The lecture's comparison table
/// says BVHs suit parallel hardware (BVH 与 GPU 并行架构匹配度高); this is that
/// idea on a CPU's vector unit, as in Wald, Benthin and Boulos, "Getting Rid of
/// Packets" (2008), Dammertz et al., "Shallow Bounding Volume Hierarchies" (2008),
/// and Embree's BVH4/BVH8.
///
/// Built by collapse_bvh() (below) from a binary Bvh: the triangles, their ids and
/// the leaves are the binary tree's; only the interior nodes change. The leaves are
/// tested four triangles at a time (leaf_lanes, geometry/triangle_lanes.h), so
/// build_accelerator builds that binary tree with an SAH that counts a leaf's tests
/// (BvhConfig::leaf_lanes = 4, sah.h): leaves of three and four, fewer nodes.
///
/// Traversal: the binary BVH's walk with a node's W children in place of its two:
/// test all W boxes at once, keep those the ray enters (and, for the closest hit,
/// that start no later than the closest hit so far), then go to the nearest and
/// push the others farthest first (algorithm 2), or take them in lane order without
/// pruning (algorithm 1). Exactness is the binary BVH's argument unchanged (bvh.h):
/// the same widened box test, box by box bit for bit, and the same leaf test.
///
/// Node ids in events ("slots"): every box in the tree has one. Slot 0 is the root's
/// box; lane i of wide node n is slot 1 + n·W + i. box_of(slot) and slot_of() turn
/// them into boxes for the window.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/bvh.h"
#include "core/geometry/triangle_lanes.h"
#include "core/math/box_lanes.h"
#include "core/util/expected.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// One wide node: W child boxes as structure of arrays, and per child where it
/// leads. Child i is empty (i >= child_count), a leaf (count[i] > 0: triangles
/// [first[i], first[i] + count[i]) in leaf order) or interior (count[i] == 0: wide
/// node first[i]). 128 bytes for W = 4, 256 for W = 8: whole cache lines.
template <int W>
struct alignas(64) WideBvhNode {
    BoxLanes<W> boxes;
    uint32_t first[W];
    uint16_t count[W];  ///< a leaf's triangle count, 0 for interior or empty (collapse_bvh refuses bigger leaves)
    uint8_t child_count = 0;

    bool is_leaf(int i) const { return count[i] > 0; }
};
static_assert(sizeof(WideBvhNode<4>) == 128 && sizeof(WideBvhNode<8>) == 256, "a wide node is whole cache lines");

/// What a wide BVH's build reports, beyond the binary build's stats (which it keeps).
struct WideBvhStats {
    int width = 4;
    uint32_t nodes = 0;           ///< wide (interior) nodes
    uint32_t leaves = 0;          ///< leaves (the binary tree's)
    uint32_t max_depth = 0;       ///< deepest leaf, the root's children at depth 1
    double avg_children = 0;      ///< children per wide node, on average
    uint32_t bytes_per_node = 0;  ///< sizeof(WideBvhNode<W>)
    double sah_cost = 0;          ///< Σ wide node S/S_root·C_trav + Σ leaf S/S_root·N·C_isect (N in tests, sah.h)
    uint64_t memory_bytes = 0;    ///< nodes, prim_ids and the leaves' triangle lanes
    double collapse_ms = 0;       ///< wall time of the collapse alone
    double build_ms = 0;          ///< binary build + collapse
};
nlohmann::json to_json(const WideBvhStats& stats);

template <int W, class Lanes = FastLanes<W>>
struct WideBvh {
    static_assert(W == 4 || W == 8, "a wide BVH has 4 or 8 children per node");
    static constexpr int kWidth = W;
    using Node = WideBvhNode<W>;

    std::vector<Node, LargeArrayAllocator<Node>> nodes;  ///< nodes[0] is the root when the root is interior
    Aabb root_bounds;            ///< the root's box (tested first, as in the binary walk)
    uint32_t root_first = 0;     ///< the root: wide node 0, or (a tree that is one leaf) its first triangle
    uint32_t root_count = 0;     ///< 0: the root is wide node 0; > 0: the root is a leaf of this many triangles
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> prim_ids;  ///< leaf order → triangle id (the binary tree's)
    /// The triangles in leaf order, each leaf's as lanes: what Möller–Trumbore's walk
    /// tests, four at a time (triangle_lanes.h). Made by make_leaf_lanes().
    LeafTriangleLanes leaf_lanes;
    CornerArray corners;         ///< leaf order; only when triangle_test is watertight
    BvhConfig build_config;
    BvhBuildStats binary_stats;  ///< the binary tree it was collapsed from
    WideBvhStats build_stats;
    BvhTraversal traversal = BvhTraversal::Ordered;
    TriangleTestKind triangle_test = TriangleTestKind::MollerTrumbore;

    static constexpr AccelType kType = AccelType::Bvh;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const;
    nlohmann::json stats() const;

    bool empty() const { return nodes.empty() && root_count == 0; }

    /// Fills `leaf_lanes` from the leaves and the triangles in leaf order (the last
    /// step of every way a wide BVH is made).
    void make_leaf_lanes(const TriangleArray& leaf_order_triangles);

    /// The box of `slot` (slot 0: the root's).
    Aabb box_of(uint32_t slot) const {
        if (slot == 0) return root_bounds;
        const uint32_t s = slot - 1;
        return nodes[s / W].boxes.get(int(s % W));
    }
    static uint32_t slot_of(uint32_t node, int lane) { return 1 + node * W + uint32_t(lane); }

    /// Every box of the tree, parents before children: f(slot, box, depth, leaf_count)
    /// with the root at depth 0 and leaf_count 0 for an interior box. What the window draws.
    template <class F>
    void for_each_box(F&& f) const {
        if (empty()) return;
        f(0u, root_bounds, 0u, root_count);
        if (root_count > 0) return;
        std::vector<std::pair<uint32_t, uint32_t>> stack = {{0u, 0u}};  // wide node, its depth
        while (!stack.empty()) {
            const auto [n, depth] = stack.back();
            stack.pop_back();
            const Node& node = nodes[n];
            for (int i = 0; i < node.child_count; ++i) {
                f(slot_of(n, i), node.boxes.get(i), depth + 1, uint32_t(node.count[i]));
                if (!node.is_leaf(i)) stack.push_back({node.first[i], depth + 1});
            }
        }
    }

    template <class Observer>
    Hit intersect_closest(const Ray& ray, Observer& obs) const {
        return traversal == BvhTraversal::Ordered ? traverse<ChildOrder::NearestFirst, StopAt::ClosestHit>(ray, obs)
                                                  : traverse<ChildOrder::LeftThenRight, StopAt::ClosestHit>(ray, obs);
    }
    template <class Observer>
    bool intersect_any(const Ray& ray, Observer& obs) const {
        return traverse<ChildOrder::NearestFirst, StopAt::AnyHit>(ray, obs).found();
    }
    bool intersect_any(const Ray& ray) const {
        NoObserver obs;
        return intersect_any(ray, obs);
    }

    /// The one traversal, its box and triangle tests picked once per ray (as Bvh::traverse).
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

    /// A child to visit now or later: where it leads (as WideBvhNode's first/count),
    /// its box's entry distance and, for events, its slot and exit distance.
    template <bool kKeepsId>
    struct StackEntry {
        uint32_t first;
        uint32_t count;
        float t_enter;
        [[no_unique_address]] KeptForEvents<uint32_t, kKeepsId> slot;
        [[no_unique_address]] KeptForEvents<float, kKeepsId> t_exit;

        bool is_leaf() const { return count > 0; }
    };
    /// Each level pushes at most W - 1 children, and the binary tree is at most
    /// kBvhMaxDepth deep, so the wide one is too.
    static constexpr int kStackSize = (W - 1) * (int(kBvhMaxDepth) + 1) + 1;

    /// A hint to the memory system: child i of `node` will be needed (its wide node's
    /// cache lines, or its leaf's triangles). Changes nothing but when memory arrives.
    template <TriangleTestKind kTest>
    [[gnu::always_inline]] void prefetch_child(const Node& node, int i) const {
        if (node.is_leaf(i)) {
            const bool lanes = kTest == TriangleTestKind::MollerTrumbore;
            const char* first = lanes ? reinterpret_cast<const char*>(leaf_lanes.leaf(node.first[i]))
                                      : reinterpret_cast<const char*>(corners.data() + node.first[i]);
            prefetch(first);
            prefetch(first + (lanes ? sizeof(Triangle) : sizeof(TriangleCorners)) * node.count[i] - 1);
        } else {
            const char* line = reinterpret_cast<const char*>(&nodes[node.first[i]]);
            for (size_t offset = 0; offset < sizeof(Node); offset += 64) prefetch(line + offset);
        }
    }

    /// intersect_leaf_triangles (bvh.h) for Möller–Trumbore, four lanes at a time
    /// (for_each_lane_test, triangle_lanes.h), each test kept as take_triangle_test keeps
    /// it. An observer that watches hears every triangle's test, as from the
    /// one-triangle loop; the fast path looks only at the candidates (no other lane can hit).
    template <StopAt kStop, class Observer>
    [[gnu::always_inline]] bool intersect_leaf_lanes(uint32_t first, uint32_t count, Ray& ray,
                                                     const BoxTestRay& box_ray, Hit& best, Observer& obs) const {
        const auto keep = [&](uint32_t k, const auto& result) __attribute__((always_inline)) {
            return take_triangle_test<kStop>(result(), prim_ids[first + k], ray, best, obs);
        };
        return for_each_lane_test<typename Lanes::Four>(leaf_lanes, first, count, ray, box_ray,
                                                        kObserverWatches<Observer>, keep);
    }
};

/// Collapses a binary BVH into a wide one (moving its triangle arrays): each wide
/// node starts from a binary node's two children and, while it has fewer than W,
/// replaces its interior child of largest surface area by that child's two
/// children: the child most rays that reach the node enter (the SAH's S_child/S_node),
/// so opening it saves the most steps (Wald et al. 2008). The leaves and their
/// triangle order are kept: a binary subtree of a few triangles would be worth making
/// one leaf only where the SAH says a leaf costs less, and the binary builder split it
/// because the same SAH said it did not (measured: docs/performance.md). Cancelling
/// `progress` (checked every 1024 wide nodes) returns WorkProgress::cancelled_error().
template <int W>
Expected<WideBvh<W>> collapse_bvh(Bvh&& binary, WorkProgress* progress = nullptr);
/// The same, into a wide BVH whose box tests use `Lanes` (the tests' scalar reference).
template <int W, class Lanes>
Expected<WideBvh<W, Lanes>> collapse_bvh_with(Bvh&& binary, WorkProgress* progress = nullptr);

// ---------------------------------------------------------------------------
// The traversal. Written once; NoObserver's empty on() makes it the fast path.
// ---------------------------------------------------------------------------

template <int W, class Lanes>
template <ChildOrder kOrder, StopAt kStop, bool kMayStartBehind, TriangleTestKind kTest, class Observer>
Hit WideBvh<W, Lanes>::walk(const Ray& ray, Observer& obs) const {
    constexpr bool kNearestFirst = kOrder == ChildOrder::NearestFirst;
    constexpr bool kClosest = kStop == StopAt::ClosestHit;
    constexpr bool kWatched = kObserverWatches<Observer>;
    using Entry = StackEntry<kWatched>;
    Hit best;
    if (empty()) return report_done(best, obs);
    const TriangleTester<kTest> tester(ray, nullptr, corners.data());  // Möller–Trumbore reads leaf_lanes
    const BoxTestRay& box_ray = tester.box_ray();
    Ray shrinking = ray;  // t_max follows the closest hit, for the triangle tests only
    Entry stack[kStackSize];
    Entry* top = stack;  // one past the last entry

    // The root's box (lecture: a ray that misses the bounding box misses every triangle).
    const SlabResult root = widened_slab_test<kMayStartBehind>(root_bounds, box_ray, ray.t_min, ray.t_max);
    const bool root_entered = root.t_enter <= root.t_exit;
    obs.on({.kind = EventKind::BoxTest, .hit = root_entered, .node = 0, .t_enter = root.t_enter, .t_exit = root.t_exit});
    if (!root_entered) {
        obs.on({.kind = EventKind::Cull, .reason = CullReason::MissedBox, .node = 0, .t_enter = root.t_enter,
                .t_exit = root.t_exit});
        return report_done(best, obs);
    }
    Entry current{root_first, root_count, root.t_enter, 0u, root.t_exit};
    while (true) {
        obs.on({.kind = EventKind::VisitNode, .node = current.slot, .t_enter = current.t_enter,
                .t_exit = current.t_exit});
        if (current.is_leaf()) {
            obs.on({.kind = EventKind::Leaf, .node = current.slot, .first = current.first, .count = current.count,
                    .t_enter = current.t_enter, .t_exit = current.t_exit});
            if constexpr (kTest == TriangleTestKind::MollerTrumbore) {
                if (intersect_leaf_lanes<kStop>(current.first, current.count, shrinking, box_ray, best, obs))
                    return report_done(best, obs);
            } else if (intersect_leaf_triangles<kStop>(current.first, current.count, prim_ids.data(), shrinking, tester,
                                                       best, obs)) {
                return report_done(best, obs);
            }
        } else {
            // All children's boxes in one go; keep those the ray enters no later than
            // the closest hit so far (algorithm 1: every one it enters).
            const Node& node = nodes[current.first];
            alignas(32) float t_enter[W], t_exit[W];
            const uint32_t entered = widened_slab_test_lanes<Lanes, kMayStartBehind>(
                node.boxes, box_ray, ray.t_min, ray.t_max, t_enter, t_exit) & ((1u << node.child_count) - 1);
            uint32_t kept = entered;
            if constexpr (kClosest && kNearestFirst) {
                // Not beyond the closest hit: !(t_enter > best.t), that is t_enter <= best.t (t_enter is never NaN).
                kept &= Lanes::less_equal(Lanes::load(t_enter), Lanes::splat(best.t));
            }
            if constexpr (kWatched) {
                for (int i = 0; i < node.child_count; ++i)
                    obs.on({.kind = EventKind::BoxTest, .hit = bool(entered >> i & 1), .node = slot_of(current.first, i),
                            .t_enter = t_enter[i], .t_exit = t_exit[i]});
                for (int i = 0; i < node.child_count; ++i)
                    if (!(kept >> i & 1))
                        obs.on({.kind = EventKind::Cull,
                                .reason = entered >> i & 1 ? CullReason::BeyondClosestHit : CullReason::MissedBox,
                                .node = slot_of(current.first, i), .t_enter = t_enter[i], .t_exit = t_exit[i]});
            }
            if (kept != 0) {
                auto entry_of = [&](int i) {
                    return Entry{node.first[i], node.count[i], t_enter[i], slot_of(current.first, i), t_exit[i]};
                };
                auto push = [&](int i) {
                    *top++ = entry_of(i);
                    obs.on({.kind = EventKind::Push, .node = top[-1].slot, .t_enter = top[-1].t_enter,
                            .t_exit = top[-1].t_exit});
                };
                // The kept leaves' triangles are the loads most likely to miss the caches:
                // ask for all of them now, so their misses may overlap (a hint only).
                for (uint32_t m = kept; m; m &= m - 1)
                    if (node.is_leaf(__builtin_ctz(m))) prefetch_child<kTest>(node, __builtin_ctz(m));
                // The kept children in visiting order: nearest first (the lower lane on a
                // tie), or lane order. The first becomes current; the rest go on the
                // stack last-first, so they come back off it in this order. One and two
                // children, the common cases, take no sorting loop.
                const int a = __builtin_ctz(kept);
                const uint32_t rest = kept & (kept - 1);
                if (rest == 0) {
                    current = entry_of(a);
                    prefetch_child<kTest>(node, a);
                    continue;
                }
                if ((rest & (rest - 1)) == 0) {
                    const int b = __builtin_ctz(rest);
                    const bool b_first = kNearestFirst && t_enter[b] < t_enter[a];
                    push(b_first ? a : b);
                    current = entry_of(b_first ? b : a);
                    prefetch_child<kTest>(node, b_first ? b : a);
                    continue;
                }
                int order[W];
                int n = 0;
                for (uint32_t m = kept; m; m &= m - 1) {
                    const int i = __builtin_ctz(m);
                    int k = n++;
                    if constexpr (kNearestFirst)
                        for (; k > 0 && t_enter[i] < t_enter[order[k - 1]]; --k) order[k] = order[k - 1];
                    order[k] = i;
                }
                for (int k = n - 1; k > 0; --k) push(order[k]);
                current = entry_of(order[0]);
                prefetch_child<kTest>(node, order[0]);
                continue;
            }
        }
        // The next deferred child, unless the closest hit has overtaken it meanwhile.
        bool found = false;
        while (top != stack) {
            const Entry next = *--top;
            obs.on({.kind = EventKind::Pop, .node = next.slot, .t_enter = next.t_enter, .t_exit = next.t_exit});
            if constexpr (kClosest && kNearestFirst) {
                if (next.t_enter > best.t) {
                    obs.on({.kind = EventKind::Cull, .reason = CullReason::BeyondClosestHit, .node = next.slot,
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

// The walks for the three observers, compiled once in wide_bvh.cpp (as bvh.h does).
#define ACCELVIZ_WIDE_WALK(EXTERN, WIDTH, LANES, ORDER, STOP, BEHIND, TEST, OBSERVER)                        \
    EXTERN template Hit WideBvh<WIDTH, LANES>::walk<ChildOrder::ORDER, StopAt::STOP, BEHIND, TriangleTestKind::TEST>( \
        const Ray&, OBSERVER&) const;
#define ACCELVIZ_WIDE_WALKS(EXTERN, WIDTH, LANES, TEST, OBSERVER)                               \
    ACCELVIZ_WIDE_WALK(EXTERN, WIDTH, LANES, NearestFirst, ClosestHit, false, TEST, OBSERVER)  \
    ACCELVIZ_WIDE_WALK(EXTERN, WIDTH, LANES, NearestFirst, ClosestHit, true, TEST, OBSERVER)   \
    ACCELVIZ_WIDE_WALK(EXTERN, WIDTH, LANES, LeftThenRight, ClosestHit, false, TEST, OBSERVER) \
    ACCELVIZ_WIDE_WALK(EXTERN, WIDTH, LANES, LeftThenRight, ClosestHit, true, TEST, OBSERVER)  \
    ACCELVIZ_WIDE_WALK(EXTERN, WIDTH, LANES, NearestFirst, AnyHit, false, TEST, OBSERVER)      \
    ACCELVIZ_WIDE_WALK(EXTERN, WIDTH, LANES, NearestFirst, AnyHit, true, TEST, OBSERVER)
#define ACCELVIZ_WIDE_TRAVERSALS(EXTERN, WIDTH)                                               \
    ACCELVIZ_WIDE_WALKS(EXTERN, WIDTH, FastLanes<WIDTH>, MollerTrumbore, NoObserver)          \
    ACCELVIZ_WIDE_WALKS(EXTERN, WIDTH, FastLanes<WIDTH>, MollerTrumbore, CountingObserver)    \
    ACCELVIZ_WIDE_WALKS(EXTERN, WIDTH, FastLanes<WIDTH>, MollerTrumbore, RecordingObserver)   \
    ACCELVIZ_WIDE_WALKS(EXTERN, WIDTH, FastLanes<WIDTH>, Watertight, NoObserver)              \
    ACCELVIZ_WIDE_WALKS(EXTERN, WIDTH, FastLanes<WIDTH>, Watertight, CountingObserver)        \
    ACCELVIZ_WIDE_WALKS(EXTERN, WIDTH, FastLanes<WIDTH>, Watertight, RecordingObserver)
ACCELVIZ_WIDE_TRAVERSALS(extern, 4)
ACCELVIZ_WIDE_TRAVERSALS(extern, 8)

}  // namespace accelviz
