#pragma once
/// A stepper's debug geometry (core/stepper: boxes, segments, filled triangles and
/// quads, labels at 3D points) drawn in the 3D view: the ray stepper's and the
/// nearest-point stepper's.

#include <memory>
#include <vector>

#include "app/gl/renderer.h"
#include "core/stepper/stepper.h"

namespace accelviz {

class DebugGeometryGl {
public:
    /// Draws `g` (context current, view begun), uploading it first when `dirty` (then
    /// cleared). Boxes at `line_width`, segments (the ray, marks) thicker.
    void draw(Renderer& renderer, const DebugGeometry& g, bool& dirty, float line_width);

private:
    std::unique_ptr<BoxBuffer> boxes_;
    std::unique_ptr<ColouredBuffer> segments_, quads_;
};

/// The labels at their 3D points over the 3D view (ImGui's background draw list); a
/// label that would cover an earlier one moves down below it.
void draw_debug_labels(const std::vector<DebugLabel>& labels, const View3D& view);

}  // namespace accelviz
