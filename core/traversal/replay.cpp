#include "core/traversal/replay.h"

#include <algorithm>

namespace accelviz {

StepState replay(const std::vector<TraversalEvent>& events, size_t k) {
    StepState s;
    k = std::min(k, events.size());
    for (size_t i = 0; i < k; ++i) {
        const TraversalEvent& e = events[i];
        s.counters.add(e);
        switch (e.kind) {
            case EventKind::BoxTest: s.last_box_test = e; break;
            case EventKind::VisitNode:
                s.visited.push_back(e.node);
                s.last_visit = e;
                break;
            case EventKind::Push: s.stack.push_back({e.node, e.t_enter, e.t_exit}); break;
            case EventKind::Pop: {
                // The popped node is normally the top; search from the top to be safe.
                auto it = std::find_if(s.stack.rbegin(), s.stack.rend(),
                                       [&](const StepState::StackEntry& x) { return x.node == e.node; });
                if (it != s.stack.rend()) s.stack.erase(std::next(it).base());
                break;
            }
            case EventKind::Cull: s.culled.push_back({e.node, e.reason, e.t_enter}); break;
            case EventKind::Leaf: break;
            case EventKind::TriangleTest:
                s.tested.push_back({e.tri, e.hit, e.t});
                s.last_triangle_test = e;
                break;
            case EventKind::NewClosest: s.closest = {e.tri, e.t, e.u, e.v}; break;
            case EventKind::EnterCell:
                s.cells.push_back(e);
                s.visited.push_back(e.node);
                s.last_visit = e;
                break;
            case EventKind::MailboxSkip: break;
            case EventKind::HitOutsideCell: s.rejected.push_back(e); break;
            case EventKind::SplitPlane: s.last_split = e; break;
            case EventKind::Done:
                s.done = true;
                s.closest = e.hit ? Hit{e.tri, e.t, e.u, e.v} : Hit{};
                break;
        }
    }
    s.steps = k;
    if (k > 0) s.current = events[k - 1];
    return s;
}

}  // namespace accelviz
