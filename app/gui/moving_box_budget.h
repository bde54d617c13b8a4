#pragma once
/// How many of the overlay's boxes a frame draws while the camera moves: whole
/// shallow levels (StructureOverlay::moving_prefix) up to a budget that follows the
/// frame time, so that turning the view stays fluid on a software renderer (where
/// every box costs microseconds) and shows deeper levels where boxes are cheap.
///
/// Two moving frames in a row slower than kTargetMs give up their deepest level (one
/// slow frame may be a hitch: a new scene's upload); two fast enough that the next
/// level would still fit, even if the whole frame grew with the boxes (a level of a
/// binary tree doubles them, of an octree up to eightfold), take it.
/// That estimate over-counts (the mesh and the panels do not grow with the boxes), so
/// a level taken fits, and a level given up is not taken again on it: the budget
/// settles instead of swinging between two levels. A level given up is taken again
/// when the frames have got faster in proportion (the machine was busy for a while):
/// its slow time, scaled by how much faster the frames are now than just after it was
/// given up, fits with a tenth to spare. The frame time is the whole frame's, the swap
/// included: a software renderer draws most of a frame when it is swapped.

#include <cstddef>

#include "app/gui/structure_overlay.h"

namespace accelviz {

class MovingBoxBudget {
public:
    /// The budget before any frame is timed (and for golden images, never timed):
    /// 12 levels of a binary BVH (a still picture's share frames draw as many,
    /// ViewCache::kStillBoxesPerFrame). One level more made the first two
    /// frames of a drag the slowest of the orbit on a software renderer
    /// (docs/performance.md); a faster machine takes the next levels two frames each.
    static constexpr size_t kStartBoxes = 4096;
    /// The fewest boxes a slow frame drops to (10 levels of a binary BVH): the frame
    /// may be slow for other reasons (a ray-cast mesh of millions of triangles).
    static constexpr size_t kFewestBoxes = 1024;
    /// A moving frame's time aimed at: 25 frames a second.
    static constexpr double kTargetMs = 40.0;

    size_t boxes() const { return budget_; }

    /// A frame begins; the previous one took `previous_frame_ms` (0: unknown). If that
    /// frame drew the overlay while moving, the budget follows its time.
    void start_frame(double previous_frame_ms, const StructureOverlay& overlay);
    /// This frame draws the overlay's moving prefix (the camera moves).
    void drew_moving() { drew_moving_ = true; }

private:
    size_t budget_ = kStartBoxes;
    bool drew_moving_ = false;
    int slow_frames_ = 0, fast_frames_ = 0;  ///< moving frames in a row over the target, or with room for a level
    size_t given_up_ = 0;              ///< the boxes of the level last given up (0: none)
    double given_up_ms_ = 0;           ///< the frame time that gave it up
    double after_giving_up_ms_ = 0;    ///< the first frame's time without it (0: not yet drawn)
    size_t overlay_boxes_ = 0;         ///< the boxes of the overlay it follows (another one starts again)
};

}  // namespace accelviz
