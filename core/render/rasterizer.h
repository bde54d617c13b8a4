#pragma once
/// The CPU z-buffer rasterizer, following the lecture's loop (基本光栅化算法):
///   for each triangle: project it; for each pixel centre in its screen bounding
///   box: coverage by edge functions (top-left fill rule); perspective-correct
///   depth; z-test against the closest so far.
/// Triangles are clipped against the near plane first, so geometry behind the eye
/// is handled. Its depth is converted to the ray distance t along the same pixel's
/// camera ray, so raster and ray-cast frames compare pixel by pixel.

#include <cstdint>

#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/render/frame.h"

namespace accelviz {

struct RasterStats {
    uint64_t triangles_in = 0;          ///< triangles submitted
    uint64_t triangles_rasterized = 0;  ///< after near-plane clipping (a clipped triangle may become two)
    uint64_t pixels_tested = 0;         ///< pixel centres tested for coverage (the bounding-box walk)
    uint64_t fragments = 0;             ///< covered pixel centres (before the z-test)
    uint64_t depth_writes = 0;          ///< fragments that passed the z-test
};

/// Rasterizes `mesh` as seen by `camera`. Frame::depth holds the ray distance t
/// (+inf where nothing is drawn); Frame::tests counts fragments per pixel.
Frame rasterize(const Mesh& mesh, const Camera& camera, RasterStats* stats = nullptr);

}  // namespace accelviz
