#pragma once
/// A frame's primary rays, generated once, and a way to trace them on N threads.
/// `bench` times ours and the reference (Embree) through the same loop, on the
/// same rays, so their ratio is measured side by side.

#include <cstdint>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/geometry/triangle.h"
#include "core/render/camera.h"

namespace accelviz::cli {

/// One ray per pixel centre (camera contract), row by row from the top.
inline std::vector<Ray> camera_rays(const Camera& camera) {
    std::vector<Ray> rays;
    rays.reserve(size_t(camera.width()) * camera.height());
    for (int y = 0; y < camera.height(); ++y)
        for (int x = 0; x < camera.width(); ++x) rays.push_back(camera.ray(x, y));
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
