#pragma once
/// The lecture's two loops side by side, stopped part-way (基本的光栅化 vs. 光线追踪):
///   rasterization: for each triangle, for each pixel it covers: the z-test;
///   ray casting:   for each pixel, for its ray: the closest triangle.
/// The rasterizer's picture after its first k triangles is replayed from the writes
/// it recorded (RasterHistory); the ray caster's after its first p pixels (row by
/// row) is the finished picture's first p pixels, since each pixel is done when its
/// ray is. Both come with the counts of the work done so far.

#include <cstdint>

#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/render/frame.h"
#include "core/render/image.h"
#include "core/render/rasterizer.h"

namespace accelviz {

/// The largest mesh whose rasterization the fill order records (its history takes 24
/// bytes per triangle and 8 per z-buffer write): the lecture's small scenes, not 10M.
inline constexpr uint64_t kFillOrderMaxTriangles = 2'000'000;

/// The rasterizer's work after its first `triangles` triangles.
struct RasterFillCounts {
    uint64_t triangles = 0, triangle_count = 0;
    uint64_t depth_tests = 0;   ///< fragments: covered pixel centres, each z-tested
    uint64_t depth_writes = 0;  ///< tests passed
    uint64_t overwrites = 0;    ///< writes over a pixel an earlier triangle had written
};

/// The ray caster's work after its first `pixels` pixels.
struct RayFillCounts {
    uint64_t pixels = 0, pixel_count = 0;  ///< one ray each
    uint64_t nodes = 0, triangle_tests = 0;  ///< 0 when the cast did not count its work
};

/// The rasterizer's picture after `triangles` of them (background elsewhere), shaded
/// as rasterize() shades. `history` is of `mesh` seen by `camera`.
Image raster_fill_image(const RasterHistory& history, const Mesh& mesh, const Camera& camera, uint64_t triangles,
                        RasterFillCounts* counts = nullptr);

/// The ray-cast `frame` after its first `pixels` pixels in row order (background after).
Image ray_cast_fill_image(const Frame& frame, uint64_t pixels, RayFillCounts* counts = nullptr);

/// How far each loop has got at `fraction` (0 to 1) of its work: the same share of
/// the triangles and of the pixels, rounded down (all of them at 1; a share within a
/// thousandth of a unit below a whole number counts as that number).
uint64_t fill_amount(double fraction, uint64_t total);

}  // namespace accelviz
