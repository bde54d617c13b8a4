#pragma once
/// The CPU z-buffer rasterizer, following the lecture's loop (基本光栅化算法):
///   for each triangle: project it; for each pixel centre in its screen bounding
///   box: coverage by edge functions (top-left fill rule); perspective-correct
///   depth; z-test against the closest so far.
/// Triangles are clipped against the near plane first, so geometry behind the eye
/// is handled. Its depth is converted to the ray distance t along the same pixel's
/// camera ray, so raster and ray-cast frames compare pixel by pixel.
///
/// The near plane: camera-space depth z = dot(p - eye, forward) >= z_near, with
///   z_near = kNearPlaneRatio * (largest distance from the eye to a finite vertex).
/// It scales with the scene and the view, so it works for unit meshes and for
/// scenes in millimetres alike. Surfaces closer to the eye than z_near are not
/// drawn (the ray caster would still see them). Depth is interpolated in double
/// precision and stored as t, not as a hyperbolic z-buffer value, so the ratio
/// can be far smaller than a GPU's near/far ratio.

#include <cstdint>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/render/frame.h"

namespace accelviz {

/// z_near / (largest distance from the eye to a vertex); see above.
inline constexpr double kNearPlaneRatio = 1e-6;

struct RasterStats {
    uint64_t triangles_in = 0;          ///< triangles submitted
    uint64_t triangles_rasterized = 0;  ///< after near-plane clipping (a clipped triangle may become two)
    uint64_t pixels_tested = 0;         ///< pixel centres tested for coverage (the bounding-box walk)
    uint64_t fragments = 0;             ///< covered pixel centres (before the z-test)
    uint64_t depth_writes = 0;          ///< fragments that passed the z-test
    double z_near = 0;                  ///< the near plane used (camera-space depth)
};

/// The rasterizer's loop as it ran, for replaying it triangle by triangle (the fill-
/// order animation, core/render/fill_order.h): every z-buffer write in order, and per
/// triangle how far the counts had got before it.
struct RasterHistory {
    std::vector<uint32_t> write_pixel;  ///< the pixel index of each depth write, in order
    std::vector<uint32_t> write_tri;    ///< the triangle that wrote it
    /// Size triangle_count + 1; entry k: the totals before triangle k (the last: all).
    std::vector<uint64_t> writes_before, fragments_before, overwrites_before;
};

/// Rasterizes `mesh` as seen by `camera`. Frame::depth holds the ray distance t
/// (+inf where nothing is drawn); Frame::tests counts fragments per pixel.
/// `history` (if given) records the writes (memory: 8 bytes per write and 24 per triangle).
Frame rasterize(const Mesh& mesh, const Camera& camera, RasterStats* stats = nullptr,
                RasterHistory* history = nullptr);

}  // namespace accelviz
