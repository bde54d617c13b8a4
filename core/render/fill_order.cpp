#include "core/render/fill_order.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/render/shading.h"

namespace accelviz {

uint64_t fill_amount(double fraction, uint64_t total) {
    if (!(fraction > 0)) return 0;
    if (fraction >= 1) return total;
    // A thousandth of a unit of slack: a share given in float (0.29f is 0.28999999...)
    // still reaches the whole number it stands for.
    return std::min(total, uint64_t(std::floor(fraction * double(total) + 1e-3)));
}

Image raster_fill_image(const RasterHistory& history, const Mesh& mesh, const Camera& camera, uint64_t triangles,
                        RasterFillCounts* counts) {
    const int width = std::max(camera.width(), 0), height = std::max(camera.height(), 0);
    Image image(width, height);
    std::fill(image.pixels.begin(), image.pixels.end(), kBackground);
    const uint64_t total = history.writes_before.empty() ? 0 : history.writes_before.size() - 1;
    triangles = std::min(triangles, total);
    // The z-buffer's triangle ids after the writes of the first `triangles` triangles:
    // the writes are in triangle order, so they are a prefix of the list.
    std::vector<uint32_t> tri(size_t(width) * size_t(height), Hit::kNoHit);
    const uint64_t writes = total > 0 ? history.writes_before[triangles] : 0;
    for (uint64_t w = 0; w < writes; ++w) tri[history.write_pixel[w]] = history.write_tri[w];
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const size_t i = size_t(y) * size_t(width) + size_t(x);
            if (tri[i] != Hit::kNoHit) image.pixels[i] = headlight_shade(mesh.triangle(tri[i]), camera.ray(x, y).dir);
        }
    if (counts) {
        counts->triangles = triangles;
        counts->triangle_count = total;
        counts->depth_writes = writes;
        counts->depth_tests = total > 0 ? history.fragments_before[triangles] : 0;
        counts->overwrites = total > 0 ? history.overwrites_before[triangles] : 0;
    }
    return image;
}

Image ray_cast_fill_image(const Frame& frame, uint64_t pixels, RayFillCounts* counts) {
    Image image = frame.colour;
    const uint64_t total = image.pixels.size();
    pixels = std::min(pixels, total);
    std::fill(image.pixels.begin() + long(pixels), image.pixels.end(), kBackground);
    if (counts) {
        *counts = RayFillCounts{pixels, total, 0, 0};
        for (uint64_t i = 0; i < pixels; ++i) {
            if (i < frame.nodes.size()) counts->nodes += frame.nodes[i];
            if (i < frame.tests.size()) counts->triangle_tests += frame.tests[i];
        }
    }
    return image;
}

}  // namespace accelviz
