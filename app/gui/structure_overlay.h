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

namespace accelviz {

struct StructureOverlay {
    std::vector<BoxInstance> boxes;
    std::vector<ColouredQuad> quads;
    int deepest_level = 0;  ///< of the whole structure (root = 0); 0 for a grid or naive
    std::string legend;     ///< one line saying what the colours mean
};

/// The overlay of `accel` under `settings` (naive: nothing).
StructureOverlay make_structure_overlay(const Accelerator& accel, const OverlaySettings& settings);

/// How the triangles are spread over the leaves (BVH, KD tree, octree) or the
/// cells (grid): counts[k] = number of leaves / cells holding k triangle
/// references. Empty for naive.
struct LeafHistogram {
    std::string what;              ///< "BVH leaves", "KD leaves", "octree leaves", "grid cells"
    std::vector<uint64_t> counts;
    uint64_t total() const;        ///< leaves / cells counted
};
LeafHistogram leaf_histogram(const Accelerator& accel);

}  // namespace accelviz
