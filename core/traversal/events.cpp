#include "core/traversal/events.h"

namespace accelviz {

std::string_view to_string(EventKind kind) {
    switch (kind) {
        case EventKind::BoxTest: return "box_test";
        case EventKind::VisitNode: return "visit_node";
        case EventKind::Push: return "push";
        case EventKind::Pop: return "pop";
        case EventKind::Cull: return "cull";
        case EventKind::Leaf: return "leaf";
        case EventKind::TriangleTest: return "triangle_test";
        case EventKind::NewClosest: return "new_closest";
        case EventKind::EnterCell: return "enter_cell";
        case EventKind::MailboxSkip: return "mailbox_skip";
        case EventKind::HitOutsideCell: return "hit_outside_cell";
        case EventKind::SplitPlane: return "split_plane";
        case EventKind::Done: return "done";
    }
    return "unknown";
}

std::string_view to_string(CullReason reason) {
    switch (reason) {
        case CullReason::None: return "none";
        case CullReason::MissedBox: return "missed_box";
        case CullReason::BeyondClosestHit: return "beyond_closest_hit";
    }
    return "unknown";
}

}  // namespace accelviz
