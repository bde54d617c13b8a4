#pragma once
/// OpenGL's rasterized frame of a whole mesh, timed to glFinish: the scaling chart's
/// "raster: OpenGL" series (core/measure/scaling.h), measured by `render --view
/// scaling` in an OSMesa context and by the window in its own. The context must be
/// current on the calling thread.

#include <cstddef>

#include "app/gl/renderer.h"
#include "core/geometry/mesh.h"
#include "core/render/camera.h"

namespace accelviz {

class RasterTimer {
public:
    explicit RasterTimer(Renderer& renderer) : renderer_(renderer) {}

    /// One frame of `mesh` seen by `camera` (its width x height, at the framebuffer's
    /// origin; the framebuffer must be at least that big), cleared, drawn and finished;
    /// milliseconds, from after the GL work queued before it. A mesh other than the
    /// last one is uploaded first, outside the time; forget() before a mesh at the same
    /// address with the same count may be another.
    double frame_ms(const Mesh& mesh, const Camera& camera);
    void forget() { uploaded_ = nullptr; }

private:
    Renderer& renderer_;
    MeshBuffer buffer_;
    const Mesh* uploaded_ = nullptr;  ///< with its triangle count: which mesh buffer_ holds
    size_t uploaded_triangles_ = 0;
};

}  // namespace accelviz
