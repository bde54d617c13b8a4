#pragma once
/// The events a traversal reports to its observer. One small tagged struct for all
/// structures, so the stepper, `trace --json` and the counters read one stream.
///
/// Which fields mean what, per kind (unused fields keep their defaults):
///   BoxTest        node, t_enter, t_exit, hit      slab test of a node's box (or the grid's box)
///   VisitNode      node, t_enter, t_exit           traversal starts working on node
///   Push           node, t_enter, t_exit           node put on the stack for later (BVH algorithm 1: the
///                                                  parent's interval, the child's box is tested when popped)
///   Pop            node, t_enter, t_exit           node taken off the stack
///   Cull           node, reason, t_enter, t_exit   node (and its subtree) skipped
///   Leaf           node, first, count, t_enter, t_exit   a leaf's triangles are about to be tested;
///                                                  [t_enter, t_exit]: the leaf's interval on the ray (BVH: its
///                                                  box's; KD/octree: the cell's [t_min, t_max])
///   TriangleTest   tri, t, u, v, hit               one Möller–Trumbore test
///   NewClosest     tri, t, u, v                    the closest hit so far improved (grid/KD/octree: or a
///                                                  deferred hit accepted on entering the cell holding it)
///   EnterCell      cell[3], node (linear id), t_enter, t_exit   grid cell walked into (the octree,
///                                                  a tree, reports VisitNode + Leaf like the KD tree)
///   MailboxSkip    tri                             already tested for this ray: not tested again
///   HitOutsideCell tri, t, t_exit                  a hit beyond the current cell/leaf: not (yet) accepted
///   SplitPlane     node, axis, split, t (t_split), near_first   KD/octree node's plane vs the ray
///                                                  (octree: three per node, near_first = starts below it;
///                                                  BSP: axis 3, a plane N.p = split facing any way,
///                                                  near_first = the back side N.p < split first)
///   Done           tri, t, u, v, hit               the final answer

#include <cstdint>
#include <string_view>

#include "core/geometry/triangle.h"

namespace accelviz {

enum class EventKind : uint8_t {
    BoxTest, VisitNode, Push, Pop, Cull, Leaf, TriangleTest, NewClosest,
    EnterCell, MailboxSkip, HitOutsideCell, SplitPlane, Done,
};

enum class CullReason : uint8_t {
    None,
    MissedBox,         ///< the ray does not pass through the node's box at all
    BeyondClosestHit,  ///< the box starts farther than the closest hit found so far
};

struct TraversalEvent {
    EventKind kind = EventKind::Done;
    CullReason reason = CullReason::None;
    uint8_t axis = 0;
    bool hit = false;         ///< BoxTest / TriangleTest verdict, Done: found a hit
    bool near_first = false;  ///< SplitPlane: the near child is the lower one (left)
    uint32_t node = 0;
    uint32_t tri = Hit::kNoHit;
    uint32_t first = 0, count = 0;
    int32_t cell[3] = {0, 0, 0};
    float t_enter = 0, t_exit = 0;
    float t = kInfinity, u = 0, v = 0;
    float split = 0;
};

std::string_view to_string(EventKind kind);
std::string_view to_string(CullReason reason);

}  // namespace accelviz
