#include "core/render/ray_caster.h"

#include <algorithm>

#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/render/shading.h"

namespace accelviz {

int effective_threads(int requested) {
    const int cores = tbb::info::default_concurrency();
    return requested <= 0 ? cores : std::min(requested, cores);
}

Frame ray_cast(const Accelerator& accel, const TriangleArray& triangles,
               const Camera& camera, const RayCastOptions& options) {
    Frame frame(camera.width(), camera.height());
    if (options.count_work) {
        frame.nodes.assign(frame.depth.size(), 0);
        frame.tests.assign(frame.depth.size(), 0);
    }
    tbb::combinable<Counters> work;  // per-thread sums, combined at the end
    auto trace_tile = [&](const tbb::blocked_range2d<int>& tile) {
        if (cancelled(options.cancel)) return;
        for (int y = tile.rows().begin(); y < tile.rows().end(); ++y)
            for (int x = tile.cols().begin(); x < tile.cols().end(); ++x) {
                const Ray ray = camera.ray(x, y);
                const size_t i = frame.index(x, y);
                Hit hit;
                if (options.count_work) {
                    CountingObserver counter;
                    hit = accel.intersect_closest(ray, counter);
                    frame.nodes[i] = uint32_t(counter.counters.nodes_visited);
                    frame.tests[i] = uint32_t(counter.counters.triangle_tests);
                    work.local() += counter.counters;
                } else {
                    hit = accel.intersect_closest(ray);
                }
                frame.depth[i] = hit.t;
                frame.tri[i] = hit.tri;
                frame.colour.pixels[i] = hit.found() ? headlight_shade(triangles[hit.tri], ray.dir) : kBackground;
            }
    };
    const tbb::blocked_range2d<int> all(0, camera.height(), 16, 0, camera.width(), 16);
    if (options.threads > 0) {
        tbb::task_arena arena(effective_threads(options.threads));
        arena.execute([&] { tbb::parallel_for(all, trace_tile); });
    } else {
        tbb::parallel_for(all, trace_tile);
    }
    if (options.count_work) work.combine_each([&](const Counters& c) { frame.work += c; });
    return frame;
}

}  // namespace accelviz
