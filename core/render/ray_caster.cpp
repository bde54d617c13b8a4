#include "core/render/ray_caster.h"

#include <algorithm>

#include <tbb/blocked_range.h>
#include <tbb/blocked_range2d.h>
#include <tbb/combinable.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "core/render/shading.h"

namespace accelviz {

namespace {

/// Traces one pixel's rays, counting each kind's work when asked.
struct PixelTracer {
    const Accelerator& accel;
    const Mesh& mesh;
    const Lighting* lighting;
    bool count;
    Counters shadow, reflection;  ///< this pixel's secondary rays' work
    uint32_t shadow_rays = 0, reflection_rays = 0;

    Hit closest(const Ray& ray, Counters* counters) const {
        if (!count) return accel.intersect_closest(ray);
        CountingObserver counter;
        const Hit hit = accel.intersect_closest(ray, counter);
        *counters += counter.counters;
        return hit;
    }

    bool blocked(const Ray& ray) {
        ++shadow_rays;
        if (!count) return accel.intersect_any(ray);
        CountingObserver counter;
        const bool any = accel.intersect_any(ray, counter);
        shadow += counter.counters;
        return any;
    }

    /// The colour of `hit`, seen along `ray`; `bounce` 0 for a camera ray.
    Rgb shade(const Hit& hit, const Ray& ray, int bounce) {
        const Triangle tri = mesh.triangle(hit.tri);
        if (!lighting) return headlight_shade(tri, ray.dir);
        if (lighting->reflections && bounce == 0 && lighting->is_mirror(hit.tri)) {
            const Ray mirrored = reflection_ray(tri, hit.u, hit.v, ray.dir);
            ++reflection_rays;
            const Hit seen = closest(mirrored, &reflection);
            return mirror_tint(seen.found() ? shade(seen, mirrored, bounce + 1) : kBackground);
        }
        const std::optional<Ray> to_light = shadow_ray(tri, hit.u, hit.v, ray.dir, lighting->light);
        const bool lit = to_light && !(lighting->shadows && blocked(*to_light));
        return point_light_shade(tri, to_light ? to_light->dir : Vec3{}, lit);
    }
};

void add_secondary(SecondaryWork& out, size_t pixel, const Counters& work, uint32_t rays,
                   tbb::combinable<SecondaryWork>& sums) {
    if (rays == 0) return;
    out.nodes[pixel] = uint32_t(work.nodes_visited);
    out.tests[pixel] = uint32_t(work.triangle_tests);
    SecondaryWork& sum = sums.local();
    sum.work += work;
    sum.rays += rays;
}

}  // namespace

int effective_threads(int requested) {
    const int cores = tbb::info::default_concurrency();
    return requested <= 0 ? cores : std::min(requested, cores);
}

Frame ray_cast(const Accelerator& accel, const Mesh& mesh,
               const Camera& camera, const RayCastOptions& options) {
    Frame frame(camera.width(), camera.height());
    if (options.count_work) {
        frame.nodes.assign(frame.depth.size(), 0);
        frame.tests.assign(frame.depth.size(), 0);
        if (options.lighting && options.lighting->shadows) {
            frame.shadow.nodes.assign(frame.depth.size(), 0);
            frame.shadow.tests.assign(frame.depth.size(), 0);
        }
        if (options.lighting && options.lighting->reflections) {
            frame.reflection.nodes.assign(frame.depth.size(), 0);
            frame.reflection.tests.assign(frame.depth.size(), 0);
        }
    }
    tbb::combinable<Counters> work;  // per-thread sums, combined at the end
    tbb::combinable<SecondaryWork> shadow_work, reflection_work;
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
                if (!hit.found()) {
                    frame.colour.pixels[i] = kBackground;
                    continue;
                }
                PixelTracer tracer{accel, mesh, options.lighting, options.count_work, {}, {}};
                frame.colour.pixels[i] = tracer.shade(hit, ray, 0);
                if (options.count_work) {
                    add_secondary(frame.shadow, i, tracer.shadow, tracer.shadow_rays, shadow_work);
                    add_secondary(frame.reflection, i, tracer.reflection, tracer.reflection_rays, reflection_work);
                }
            }
    };
    const tbb::blocked_range2d<int> all(0, camera.height(), 16, 0, camera.width(), 16);
    if (options.threads > 0) {
        tbb::task_arena arena(effective_threads(options.threads));
        arena.execute([&] { tbb::parallel_for(all, trace_tile); });
    } else {
        tbb::parallel_for(all, trace_tile);
    }
    if (options.count_work) {
        work.combine_each([&](const Counters& c) { frame.work += c; });
        // (No structured binding here: Clang 14, the fuzzers' compiler, cannot capture one.)
        const std::pair<tbb::combinable<SecondaryWork>*, SecondaryWork*> kinds[] = {
            {&shadow_work, &frame.shadow}, {&reflection_work, &frame.reflection}};
        for (const auto& kind : kinds) {
            SecondaryWork* out = kind.second;
            kind.first->combine_each([out](const SecondaryWork& s) {
                out->work += s.work;
                out->rays += s.rays;
            });
        }
    }
    return frame;
}

ShadowQueryWork measure_shadow_queries(const Accelerator& accel, const Mesh& mesh, const Camera& camera,
                                       const Lighting& lighting, int threads) {
    tbb::combinable<ShadowQueryWork> sums;
    auto trace_rows = [&](const tbb::blocked_range<int>& rows) {
        ShadowQueryWork& sum = sums.local();
        for (int y = rows.begin(); y < rows.end(); ++y)
            for (int x = 0; x < camera.width(); ++x) {
                const Ray ray = camera.ray(x, y);
                const Hit hit = accel.intersect_closest(ray);
                if (!hit.found() || lighting.is_mirror(hit.tri)) continue;
                const std::optional<Ray> segment = shadow_ray(mesh.triangle(hit.tri), hit.u, hit.v, ray.dir, lighting.light);
                if (!segment) continue;
                CountingObserver any, closest;
                const bool blocked = accel.intersect_any(*segment, any);
                const bool found = accel.intersect_closest(*segment, closest).found();
                ++sum.rays;
                sum.blocked += blocked ? 1 : 0;
                sum.disagreed += blocked != found ? 1 : 0;
                sum.any_hit += any.counters;
                sum.closest_hit += closest.counters;
                if (blocked) {
                    sum.any_hit_blocked += any.counters;
                    sum.closest_hit_blocked += closest.counters;
                }
            }
    };
    const tbb::blocked_range<int> all(0, camera.height(), 8);
    tbb::task_arena arena(effective_threads(threads));
    arena.execute([&] { tbb::parallel_for(all, trace_rows); });
    ShadowQueryWork total;
    sums.combine_each([&](const ShadowQueryWork& s) {
        total.rays += s.rays;
        total.blocked += s.blocked;
        total.disagreed += s.disagreed;
        total.any_hit += s.any_hit;
        total.closest_hit += s.closest_hit;
        total.any_hit_blocked += s.any_hit_blocked;
        total.closest_hit_blocked += s.closest_hit_blocked;
    });
    return total;
}

}  // namespace accelviz
