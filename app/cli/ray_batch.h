#pragma once
/// A frame's primary rays, generated once, and a way to trace them on N threads.
/// `bench` times ours and the reference (Embree) through the same loop, on the
/// same rays, so their ratio is measured side by side.

#include <algorithm>
#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/geometry/triangle.h"
#include "core/render/camera.h"

namespace accelviz::cli {

/// Side of the square tiles rays are traced in: the ray caster's (render) tile size.
inline constexpr int kRayTile = 16;

/// One ray per pixel centre (camera contract), in kRayTile x kRayTile tiles (row by
/// row within a tile, tiles row by row), the order the ray caster traces them in:
/// neighbouring rays visit mostly the same nodes, which keeps those in the cache.
inline std::vector<Ray> camera_rays(const Camera& camera) {
    std::vector<Ray> rays;
    rays.reserve(size_t(camera.width()) * camera.height());
    for (int tile_y = 0; tile_y < camera.height(); tile_y += kRayTile)
        for (int tile_x = 0; tile_x < camera.width(); tile_x += kRayTile)
            for (int y = tile_y; y < std::min(tile_y + kRayTile, camera.height()); ++y)
                for (int x = tile_x; x < std::min(tile_x + kRayTile, camera.width()); ++x)
                    rays.push_back(camera.ray(x, y));
    return rays;
}

/// What a frame found per ray: t (+inf on a miss) and the triangle id (Hit::kNoHit).
struct RayResults {
    std::vector<float> t;
    std::vector<uint32_t> tri;

    explicit RayResults(size_t count = 0) : t(count, kInfinity), tri(count, Hit::kNoHit) {}
    uint64_t hit_count() const {
        uint64_t n = 0;
        for (uint32_t id : tri) n += id != Hit::kNoHit;
        return n;
    }
    /// Sum of t over hits, in ray order (so the same on every run).
    double depth_sum() const {
        double sum = 0;
        for (size_t i = 0; i < t.size(); ++i)
            if (tri[i] != Hit::kNoHit) sum += t[i];
        return sum;
    }
};

/// Calls trace(begin, end) over [0, count) in chunks, on `threads` threads (1: the
/// calling thread alone, no task scheduler; 0: all cores).
template <class Trace>
void for_each_ray_chunk(size_t count, int threads, Trace&& trace) {
    if (threads == 1) {
        trace(size_t(0), count);
        return;
    }
    tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
    arena.execute([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 2048),
                          [&](const tbb::blocked_range<size_t>& r) { trace(r.begin(), r.end()); });
    });
}

}  // namespace accelviz::cli
