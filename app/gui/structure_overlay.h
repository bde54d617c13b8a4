#pragma once
/// What the 3D view draws of a structure: wireframe boxes (BVH nodes, octree
/// cells, grid cells) and translucent rectangles (KD split planes), as plain
/// data, read from the structure's own flat arrays. No GL here: the Session
/// uploads the result once per change, and the Renderer draws every box in one
/// instanced call.
///
/// Colours: BVH, KD and octree levels by depth on the viridis-like colour map
/// (root dark blue ... deepest yellow, over the levels shown); grid cells by
/// their triangle count (few: blue ... many: yellow).

#include <string>
#include <vector>

#include "app/gl/renderer.h"
#include "app/gui/app_state.h"
#include "core/accel/accelerator.h"
#include "core/exchange/structure_check.h"

namespace accelviz {

struct StructureOverlay {
    /// BVH, KD tree and octree: by level, the shallowest first (the structure's own
    /// order within a level), so the first level_ends[k] boxes are levels lo..lo+k
    /// of those shown: a moving camera draws a prefix. The grid: by cell.
    std::vector<BoxInstance> boxes;
    std::vector<size_t> level_ends;  ///< empty for the grid
    /// The boxes a moving camera draws: whole shallow levels, at most `budget`
    /// boxes (at least the first level with boxes); all of them for the grid.
    size_t moving_prefix(size_t budget) const;
    /// The boxes of one level more than moving_prefix(budget) (as many if none is left).
    size_t deeper_prefix(size_t budget) const;
    /// The KD tree's planes of those same levels (quads are in level order too).
    size_t moving_quads(size_t budget) const;
    std::vector<ColouredQuad> quads;
    std::vector<size_t> quad_level_ends;  ///< as level_ends, for the quads (KD planes)
    int deepest_level = 0;  ///< of the whole structure (root = 0); 0 for a grid or naive
    std::string legend;     ///< one line saying what the colours mean

private:
    /// How many of the levels shown a moving camera draws.
    size_t moving_levels(size_t budget) const;
};

/// The overlay of `accel` under `settings` (naive: nothing).
StructureOverlay make_structure_overlay(const Accelerator& accel, const OverlaySettings& settings);

/// The overlay of a structure file that is not valid (check_structure found problems):
/// its own nodes by depth (BVH boxes, KD planes, grid cells), every node a problem
/// names in red whatever the levels shown.
StructureOverlay make_file_overlay(const StructureFile& file, const StructureCheck& check,
                                   const OverlaySettings& settings);

/// How the triangles are spread over the leaves (BVH, KD tree, octree) or the
/// cells (grid): counts[k] = number of leaves / cells holding k triangle
/// references. Empty for naive.
struct LeafHistogram {
    std::string what;              ///< "BVH leaves", "KD leaves", "octree leaves", "grid cells"
    std::vector<uint64_t> counts;
    uint64_t total() const;        ///< leaves / cells counted
};
LeafHistogram leaf_histogram(const Accelerator& accel);

/// The red of a node that `check` faults (the overlay's and the construction stepper's).
inline constexpr Rgba8 kFaultRed{255, 40, 40, 255};
/// A box from a file that can be drawn: every coordinate finite.
bool finite_box(const Aabb& b);

}  // namespace accelviz
