#pragma once
/// Stepping is replay (docs/architecture.md): a traversal is recorded once, and the state
/// after any step k is computed from events[0..k) by this pure function. Stepping
/// back is as cheap as stepping forward, and what the stepper shows is exactly
/// what the traversal did.

#include <optional>
#include <vector>

#include "core/traversal/observers.h"

namespace accelviz {

/// Everything the stepper shows after some number of events.
struct StepState {
    struct StackEntry {
        uint32_t node;
        float t_enter;  ///< entry distance of the node's box (or interval start)
        float t_exit;
    };
    struct Culled {
        uint32_t node;
        CullReason reason;
        float t_enter;
    };
    struct TestedTriangle {
        uint32_t tri;
        bool hit;
        float t;
    };

    size_t steps = 0;                          ///< events applied
    std::optional<TraversalEvent> current;     ///< the last event applied
    std::vector<StackEntry> stack;             ///< bottom first: the top is stack.back()
    std::vector<uint32_t> visited;             ///< nodes (or linear cell ids) visited, in order
    std::vector<Culled> culled;                ///< nodes skipped, with the reason
    std::vector<TestedTriangle> tested;        ///< triangle tests so far, in order
    std::vector<TraversalEvent> cells;         ///< EnterCell events so far (grid/octree walk)
    std::vector<TraversalEvent> rejected;      ///< HitOutsideCell events so far
    std::optional<TraversalEvent> last_box_test;       ///< for the slab inspector
    std::optional<TraversalEvent> last_triangle_test;  ///< for the triangle inspector
    std::optional<TraversalEvent> last_split;          ///< KD/octree plane of the current node
    std::optional<TraversalEvent> last_visit;          ///< the node or cell being worked on (VisitNode, EnterCell)
    Hit closest;                               ///< closest hit so far
    Counters counters;                         ///< work so far
    bool done = false;
};

/// The state after applying events[0 .. k) (k is clamped to events.size()).
StepState replay(const std::vector<TraversalEvent>& events, size_t k);

}  // namespace accelviz
