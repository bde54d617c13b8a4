#include "app/gui/moving_box_budget.h"

#include <algorithm>

namespace accelviz {

void MovingBoxBudget::start_frame(double previous_frame_ms, const StructureOverlay& overlay) {
    // Another overlay (a new scene or structure, other levels shown) starts again from
    // kStartBoxes: a level learned on one tree is not the same number of boxes on
    // another, and a budget grown on a small scene would stall a big one's first frames.
    if (overlay.boxes.size() != overlay_boxes_) {
        *this = MovingBoxBudget{};
        overlay_boxes_ = overlay.boxes.size();
    }
    // A still frame between starts the counting again; an overlay without levels (a
    // grid: every cell is drawn) has no budget to follow.
    if (!drew_moving_ || previous_frame_ms <= 0 || overlay.level_ends.empty()) {
        drew_moving_ = false;
        slow_frames_ = fast_frames_ = 0;
        return;
    }
    drew_moving_ = false;
    const size_t drawn = overlay.moving_prefix(budget_), deeper = overlay.deeper_prefix(budget_);
    const bool slow = previous_frame_ms > kTargetMs && drawn > kFewestBoxes;
    if (given_up_ == deeper && after_giving_up_ms_ == 0) after_giving_up_ms_ = previous_frame_ms;
    const bool faster_again = given_up_ == deeper && after_giving_up_ms_ > 0 &&
                              given_up_ms_ * previous_frame_ms / after_giving_up_ms_ < 0.9 * kTargetMs;
    const bool fast = drawn > 0 && deeper > drawn &&
                      (previous_frame_ms * double(deeper) / double(drawn) < kTargetMs || faster_again);
    slow_frames_ = slow ? slow_frames_ + 1 : 0;
    fast_frames_ = fast ? fast_frames_ + 1 : 0;
    if (slow_frames_ == 2) {  // one level fewer
        budget_ = std::max(kFewestBoxes, drawn - 1);
        given_up_ = drawn;
        given_up_ms_ = previous_frame_ms;
        after_giving_up_ms_ = 0;
    }
    if (fast_frames_ == 2) {
        budget_ = deeper;
        given_up_ = 0;
    }
    if (slow_frames_ == 2 || fast_frames_ == 2) slow_frames_ = fast_frames_ = 0;
}

}  // namespace accelviz
