#pragma once
/// The front-to-back walk the space-partitioning trees (KD tree, octree, BSP tree) make:
/// the ray enters the root's box (the lecture's slab test), goes down to the
/// leaf holding the start of its interval while deferring the far parts on a
/// stack, tests that leaf's triangles under the in-cell rule (cell_hits.h), and
/// goes on with the nearest deferred part that may still hold a closer hit
/// (early termination). How a node splits the interval (one plane, or three
/// centre planes) is each tree's own; this is the rest, written once.

#include <cstdint>
#include <vector>

#include "core/accel/cell_hits.h"
#include "core/geometry/triangle.h"
#include "core/math/aabb.h"
#include "core/math/ray.h"
#include "core/traversal/observers.h"

namespace accelviz {

template <int kStackSize>
struct CellWalk {
    /// A node and the part [t_min, t_max] of the ray inside it.
    struct Entry {
        uint32_t node;
        float t_min, t_max;
    };
    Entry stack[kStackSize];
    int stack_size = 0;

    /// The ray against the root's box: true, with `cur` the root and the ray's part
    /// in it, if it enters it within [ray.t_min, ray.t_max]; false after a MissedBox
    /// cull. (Where the walk is, `cur`, stays a local of the caller's loop, so the
    /// compiler keeps it in registers.)
    template <class Observer>
    [[gnu::always_inline]] bool start(const Aabb& bounds, const RayPrecomp& pre, const Ray& ray, Entry& cur,
                                      Observer& obs) const {
        const SlabResult root = slab_test(bounds, pre, ray.t_min, ray.t_max);
        obs.on({.kind = EventKind::BoxTest, .hit = root.hit(), .node = 0, .t_enter = root.t_enter,
                .t_exit = root.t_exit});
        if (!(root.t_enter <= root.t_exit)) {
            obs.on({.kind = EventKind::Cull, .reason = CullReason::MissedBox, .node = 0, .t_enter = root.t_enter,
                    .t_exit = root.t_exit});
            return false;
        }
        cur = {0, root.t_enter, root.t_exit};
        return true;
    }

    /// Defers `e` (a far part of the current node) for later.
    template <class Observer>
    void push(const Entry& e, Observer& obs) {
        stack[stack_size++] = e;
        obs.on({.kind = EventKind::Push, .node = e.node, .t_enter = e.t_min, .t_exit = e.t_max});
    }

    /// `cur` is a leaf holding the triangles prim_ids[first, first + count), at
    /// triangles[first, first + count) (leaf order) or, kViaCopyIndex, at
    /// triangles[copy_index[k]] (PartitionTree): they are tested, a hit counting only
    /// inside [cur.t_min, cur.t_max] (closest hit; any-hit: the first hit anywhere on the
    /// ray ends the leaf). True when no deferred part can hold a closer hit, or any-hit
    /// found one (the walk may stop).
    template <bool kViaCopyIndex, class Hits, class Observer>
    static bool test_leaf(const Entry& cur, uint32_t first, uint32_t count, const uint32_t* prim_ids,
                          const uint32_t* copy_index, Hits& hits, Observer& obs) {
        obs.on({.kind = EventKind::Leaf, .node = cur.node, .first = first, .count = count, .t_enter = cur.t_min,
                .t_exit = cur.t_max});
        hits.enter(cur.t_max, obs);
        for (uint32_t k = first; k < first + count && !hits.found_any(); ++k)
            hits.test(kViaCopyIndex ? copy_index[k] : k, prim_ids[k], obs);
        return hits.can_stop();
    }

    /// test_leaf for Möller–Trumbore on a leaf kept as lanes (LeafTriangleLanes): four
    /// triangles' first halves at once (for_each_lane_test, triangle_lanes.h), then each
    /// lane in leaf order through CellHits::test_lane, which makes test()'s calls and
    /// events. Without an observer that watches or a mailbox that must record every id,
    /// only the candidates are looked at (no other lane can hit).
    template <class Lanes, class Hits, class Observer>
    static bool test_leaf_lanes(const Entry& cur, uint32_t first, uint32_t count, const uint32_t* prim_ids,
                                const LeafTriangleLanes& lanes, Hits& hits, Observer& obs) {
        obs.on({.kind = EventKind::Leaf, .node = cur.node, .first = first, .count = count, .t_enter = cur.t_min,
                .t_exit = cur.t_max});
        hits.enter(cur.t_max, obs);
        const auto test = [&](uint32_t k, const auto& result) __attribute__((always_inline)) {
            hits.test_lane(result, prim_ids[first + k], obs);
            return hits.found_any();
        };
        for_each_lane_test<Lanes>(lanes, first, count, hits.test_ray(), hits.box_ray(),
                                  kObserverWatches<Observer> || hits.uses_mailbox(), test);
        return hits.can_stop();
    }

    /// Sets `cur` to the nearest deferred part that begins no farther than the
    /// closest hit so far (the others are culled); false when none is left.
    template <class Hits, class Observer>
    bool pop_next(const Hits& hits, Entry& cur, Observer& obs) {
        while (stack_size > 0) {
            const Entry e = stack[--stack_size];
            obs.on({.kind = EventKind::Pop, .node = e.node, .t_enter = e.t_min, .t_exit = e.t_max});
            if (e.t_min > hits.best().t) {
                obs.on({.kind = EventKind::Cull, .reason = CullReason::BeyondClosestHit, .node = e.node,
                        .t_enter = e.t_min, .t_exit = e.t_max});
                continue;
            }
            cur = e;
            return true;
        }
        return false;
    }

    /// At a node cut by one plane that the ray crosses at `t_split` (NaN: it lies in the
    /// plane), `near` the child holding the ray's start side and `far` the other:
    /// `cur` becomes the near child alone (crossing after the interval, never, or
    /// NaN: either side holds every triangle near the plane, thanks to the padding),
    /// the far child alone (crossed before the interval), or the near part with the
    /// far part deferred. An empty leaf holds nothing to test: skipped.
    template <class Node, class Observer>
    void cross_plane(Entry& cur, float t_split, uint32_t near, uint32_t far, const Node* nodes, Observer& obs) {
        if (!(t_split < cur.t_max)) {
            cur.node = near;
        } else if (t_split <= cur.t_min) {
            cur.node = far;
        } else {
            const Node& n = nodes[near];
            const Node& f = nodes[far];
            if (n.is_empty_leaf()) {
                cur.node = far;
                cur.t_min = t_split;
            } else {
                if (!f.is_empty_leaf()) push({far, t_split, cur.t_max}, obs);
                cur.node = near;
                cur.t_max = t_split;
            }
        }
    }

    /// The walk arrives at `cur`.
    template <class Observer>
    static void visit(const Entry& cur, Observer& obs) {
        obs.on({.kind = EventKind::VisitNode, .node = cur.node, .t_enter = cur.t_min, .t_exit = cur.t_max});
    }
};

}  // namespace accelviz
