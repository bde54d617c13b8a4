#pragma once
/// Shared by the grid, KD tree and octree tests: a scene with its seeded rays
/// and brute-force answers (computed once per scene per test process), and the
/// checks every configuration must pass.

#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include <tbb/parallel_for.h>

#include "accel/accel_test_support.h"
#include "core/geometry/scene.h"
#include "test_support.h"

namespace accelviz::test {

/// 100,000 rays per configuration (a quarter in a sanitized build).
inline constexpr size_t kRaysPerConfig = rays_for_this_build(100000);

struct SceneCase {
    Mesh mesh;
    std::vector<Ray> rays;
    std::vector<Hit> answers;  ///< brute force, ray by ray
};

/// "bunny" (the shared asset) or a load_scene() source. Cached: a test process
/// computes each scene's brute-force answers once and reuses them across configs.
inline const SceneCase& scene_case(const std::string& source, size_t ray_count = kRaysPerConfig) {
    static std::mutex mutex;
    static std::map<std::string, std::unique_ptr<SceneCase>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    const std::string key = source + "#" + std::to_string(ray_count);
    auto& slot = cache[key];
    if (!slot) {
        auto mesh = source == "bunny" ? load_obj(shared_asset("bunny.obj")) : load_scene(source);
        if (!mesh.ok()) throw std::runtime_error(mesh.error());
        slot = std::make_unique<SceneCase>();
        slot->mesh = std::move(*mesh);
        slot->rays = make_test_rays(slot->mesh, ray_count, 20261122);
        slot->answers = brute_force_answers(slot->mesh, slot->rays);
    }
    return *slot;
}

/// Every ray: same triangle, bit-identical t, u, v as brute force. Reports the first few differences.
template <class S>
void expect_exact(const S& structure, const SceneCase& scene, const std::string& label) {
    std::atomic<size_t> wrong{0};
    std::mutex report_mutex;
    std::vector<std::string> reports;
    tbb::parallel_for(size_t(0), scene.rays.size(), [&](size_t i) {
        NoObserver none;
        const Hit h = structure.intersect_closest(scene.rays[i], none);
        if (!same_hit(h, scene.answers[i])) {
            if (wrong.fetch_add(1) < 5) {
                std::lock_guard<std::mutex> lock(report_mutex);
                reports.push_back("ray #" + std::to_string(i) + " " + describe(scene.rays[i]) + ": got " +
                                  describe(h) + ", brute force " + describe(scene.answers[i]));
            }
        }
    });
    EXPECT_EQ(wrong.load(), 0u) << label << " on " << scene.mesh.name << ":\n  " << [&] {
        std::string all;
        for (const auto& r : reports) all += r + "\n  ";
        return all;
    }();
}

/// For every `stride`-th ray: the recorded trace ends in a Done event holding the
/// fast path's answer, and the recorded events count what CountingObserver counts.
template <class S>
void expect_trace_agrees(const S& structure, const SceneCase& scene, size_t stride, const std::string& label) {
    size_t bad = 0;
    for (size_t i = 0; i < scene.rays.size(); i += stride) {
        NoObserver none;
        RecordingObserver recorder;
        CountingObserver counter;
        const Hit fast = structure.intersect_closest(scene.rays[i], none);
        const Hit recorded = structure.intersect_closest(scene.rays[i], recorder);
        structure.intersect_closest(scene.rays[i], counter);
        const bool ok = !recorder.events.empty() && recorder.events.back().kind == EventKind::Done &&
                        same_hit(fast, recorded) && recorder.events.back().tri == fast.tri &&
                        (!fast.found() || recorder.events.back().t == fast.t) &&
                        recorder.counters() == counter.counters;
        if (!ok && ++bad <= 3) ADD_FAILURE() << label << ": trace disagrees for " << describe(scene.rays[i]);
    }
    EXPECT_EQ(bad, 0u) << label;
}

/// Rays whose origins lie exactly on the given planes (planes[a] on axis a):
/// moving along the plane (±0 component), through it, and from a point where
/// three planes meet (a cell corner). Brute force answers them for comparison.
inline SceneCase rays_on_planes(const Mesh& mesh, const std::array<std::vector<float>, 3>& planes, size_t count,
                                uint64_t seed) {
    SceneCase c;
    c.mesh = mesh;
    Aabb b = mesh.bounds();
    if (b.empty()) b = {{-1, -1, -1}, {1, 1, 1}};
    Rng rng(seed);
    for (size_t i = 0; i < count; ++i) {
        Ray ray;
        ray.origin = random_point_in(rng, b);
        ray.dir = random_direction(rng);
        const int axis = int(rng.below(3));
        auto pick = [&](int a) {
            if (!planes[a].empty()) ray.origin[a] = planes[a][rng.below(planes[a].size())];
        };
        switch (i % 4) {
            case 0: pick(axis); ray.dir[axis] = signed_zero(rng); break;  // along the plane
            case 1: pick(axis); break;                                      // through it
            case 2: pick(0); pick(1); pick(2); break;                       // from a corner
            default:                                                       // from a corner, axis-aligned
                pick(0); pick(1); pick(2);
                ray.dir = {signed_zero(rng), signed_zero(rng), signed_zero(rng)};
                ray.dir[axis] = rng.below(2) ? 1.0f : -1.0f;
                break;
        }
        c.rays.push_back(ray);
    }
    c.answers = brute_force_answers(c.mesh, c.rays);
    return c;
}

/// Rays no camera makes: zero, NaN, infinite and subnormal components, empty
/// and inverted ranges, corner to corner. A structure must answer each exactly
/// as brute force does.
inline std::vector<Ray> degenerate_rays(const Mesh& mesh) {
    const Aabb b = mesh.bounds().empty() ? Aabb{{-1, -1, -1}, {1, 1, 1}} : mesh.bounds();
    const Vec3 c = b.center();
    const float nan = std::numeric_limits<float>::quiet_NaN(), inf = kInfinity, tiny = 1e-40f;
    std::vector<Ray> rays = {
        {c, {0, 0, 0}},
        {c, {-0.0f, 0.0f, -0.0f}},
        {{nan, c.y, c.z}, {1, 0, 0}},
        {c, {nan, 1, 0}},
        {{-inf, c.y, c.z}, {1, 0, 0}},
        {c, {inf, 1, 0}},
        {c, {tiny, 1, -tiny}},
        {b.lo, {tiny, 0, 1}},
        {c, {1, 0, 0}, 5.0f, 1.0f},  // t_min > t_max
        {c, {1, 0, 0}, 0.0f, 0.0f},  // empty range
        {c, {0, 1, 0}, -kInfinity, kInfinity},
        {b.lo, normalize(b.hi - b.lo)},  // corner to corner, along the diagonal
        {b.hi, normalize(b.lo - b.hi)},
    };
    // From 30 scene sizes away (within the stated precision), aimed at triangle centroids.
    const float diagonal = std::max(length(b.extent()), 1e-3f);
    Rng rng(77);
    for (int i = 0; i < 200; ++i) {
        const Vec3 origin = c + random_direction(rng) * (30.0f * diagonal);
        const Vec3 aim = mesh.triangle_count() ? mesh.triangle_bounds(rng.below(mesh.triangle_count())).center() : c;
        rays.push_back({origin, normalize(aim - origin)});
    }
    return rays;
}

/// Rays beyond the structures' stated precision (reference_padding): origins a
/// million scene sizes away, where the hit points' rounding exceeds the margin,
/// and all-subnormal directions, whose t overflows to infinity. Brute force's
/// answer means little there; a structure must still answer (no hang, no crash).
inline std::vector<Ray> extreme_rays(const Mesh& mesh) {
    const Aabb b = mesh.bounds().empty() ? Aabb{{-1, -1, -1}, {1, 1, 1}} : mesh.bounds();
    const Vec3 c = b.center();
    return {{c + Vec3{1e6f, 1e6f, 1e6f}, normalize(Vec3{-1, -1, -1})},
            {c + Vec3{3e30f, 0, 0}, {-1, 0, 0}},
            {c, {1e-40f, 1e-40f, 1e-40f}},
            {c, {-1e-45f, 1e-45f, 0}}};
}

template <class S>
void expect_degenerate_rays_answered(const S& structure, const Mesh& mesh, const std::string& label) {
    const BruteForce brute(mesh);
    for (const Ray& ray : degenerate_rays(mesh)) {
        NoObserver none;
        RecordingObserver rec;
        const Hit expected = brute.intersect_closest(ray, none);
        const Hit got = structure.intersect_closest(ray, none);
        structure.intersect_closest(ray, rec);
        ASSERT_FALSE(rec.events.empty()) << label;
        EXPECT_EQ(rec.events.back().kind, EventKind::Done) << label;
        EXPECT_LT(rec.events.size(), 1000000u) << label << " " << describe(ray);
        EXPECT_TRUE(same_hit(got, expected)) << label << " " << describe(ray) << ": got " << describe(got)
                                             << ", brute force " << describe(expected);
    }
    for (const Ray& ray : extreme_rays(mesh)) {
        RecordingObserver rec;
        structure.intersect_closest(ray, rec);
        ASSERT_FALSE(rec.events.empty()) << label;
        EXPECT_EQ(rec.events.back().kind, EventKind::Done) << label;
    }
}

}  // namespace accelviz::test
