// Beyond the first hit: the any-hit query of shadow rays through every structure
// (exact against brute force on segments), the start moved off the surface (no
// shadow acne at any scale), reflections, and the ray caster's lit pictures being
// the same through every structure.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "accel/accel_test_support.h"
#include "core/accel/brute_force.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/lighting.h"
#include "core/render/ray_caster.h"
#include "core/stepper/stepper.h"
#include "test_support.h"

using namespace accelviz;

namespace {

/// Shadow-ray-like segments over `mesh`: from a random point just off a random
/// triangle (either side) to a random point in the scene's box grown by half, t in
/// [0, 1]; every fourth from one random point in the box to another, every eighth
/// along an axis.
std::vector<Ray> shadow_segments(const Mesh& mesh, size_t count, uint64_t seed) {
    Rng rng(seed);
    const TriangleArray triangles = make_triangles(mesh);
    Aabb box = mesh.bounds();
    const Vec3 grow = (box.hi - box.lo) * 0.5f;
    const Aabb wide{box.lo - grow, box.hi + grow};
    std::vector<Ray> rays;
    while (rays.size() < count) {
        const Vec3 end = test::random_point_in(rng, wide);
        Vec3 start = test::random_point_in(rng, wide);
        if (rays.size() % 4 != 0 && !triangles.empty()) {
            const Triangle& tri = triangles[rng.below(triangles.size())];
            if (!(tri.edge1.x == tri.edge1.x)) continue;  // zero area: never hit, no surface
            float u = rng.uniform(0.0f, 1.0f), v = rng.uniform(0.0f, 1.0f);
            if (u + v > 1) u = 1 - u, v = 1 - v;
            start = point_off_surface(tri, u, v, test::random_direction(rng));
        }
        Vec3 dir = end - start;
        if (rays.size() % 8 == 1) {  // along an axis, as far as the segment reaches on it
            const int a = int(rng.below(3));
            dir = Vec3{a == 0 ? dir.x : 0.0f, a == 1 ? dir.y : 0.0f, a == 2 ? dir.z : 0.0f};
        }
        if (dir == Vec3{0, 0, 0}) continue;
        rays.push_back(Ray{start, dir, 0.0f, 1.0f});
    }
    return rays;
}

void check_any_hit(const std::string& source, uint64_t seed) {
    auto mesh = load_scene(source);
    ASSERT_TRUE(mesh) << mesh.error();
    const std::vector<Ray> rays = shadow_segments(*mesh, 3000, seed);
    for (const auto& [label, config] : test::all_configurations()) {
        SCOPED_TRACE(label + " on " + source);
        const BruteForce brute(*mesh, config.triangle_test);
        auto built = build_accelerator(*mesh, config);
        ASSERT_TRUE(built) << built.error();
        const Accelerator& accel = **built;
        size_t wrong = 0, blocked = 0;
        for (const Ray& ray : rays) {
            const bool want = brute.intersect_any(ray);
            CountingObserver counted, closest_counted;
            RecordingObserver recorded;
            const bool any = accel.intersect_any(ray);
            const bool any_counted = accel.intersect_any(ray, counted);
            const bool any_recorded = accel.intersect_any(ray, recorded);
            accel.intersect_closest(ray, closest_counted);
            blocked += want ? 1 : 0;
            const bool agree = any == want && any_counted == want && any_recorded == want && !recorded.events.empty() &&
                               recorded.events.back().kind == EventKind::Done && recorded.events.back().hit == want;
            // The same walk, stopped at the first hit: never more triangle tests than the closest hit's.
            const bool no_more_work =
                counted.counters.triangle_tests <= closest_counted.counters.triangle_tests &&
                counted.counters.nodes_visited <= closest_counted.counters.nodes_visited;
            if (agree && no_more_work) continue;
            if (wrong++ < 3)
                ADD_FAILURE() << test::describe(ray) << ": any-hit " << any << "/" << any_counted << "/" << any_recorded
                              << ", brute force " << want << "; tests " << counted.counters.triangle_tests
                              << " against the closest hit's " << closest_counted.counters.triangle_tests;
        }
        EXPECT_EQ(wrong, 0u);
        EXPECT_GT(blocked, rays.size() / 20) << "the segments must test blocked rays too";
        EXPECT_LT(blocked, rays.size()) << "... and free ones";
    }
}

TEST(AnyHitQuery, EveryStructureAgreesWithBruteForceOnTheCornellBox) { check_any_hit("builtin:cornell", 11); }
TEST(AnyHitQuery, EveryStructureAgreesWithBruteForceOnTheTeapot) { check_any_hit("builtin:teapot?n=6", 12); }
TEST(AnyHitQuery, EveryStructureAgreesWithBruteForceOnASoup) { check_any_hit("builtin:soup?n=1500&seed=3", 13); }
TEST(AnyHitQuery, EveryStructureAgreesWithBruteForceWhenAllBoxesAreEqual) {
    check_any_hit("builtin:same-box?n=100", 14);
}
TEST(AnyHitQuery, EveryStructureAgreesWithBruteForceInTheStadium) { check_any_hit("builtin:stadium", 15); }

/// A tilted floor of n x n quads (2n^2 triangles) around `centre`, `size` across,
/// turned about an oblique axis so that no coordinate is round: neighbouring
/// triangles are coplanar only up to float rounding, where acne would show.
Mesh tilted_floor(int n, float size, Vec3 centre) {
    Mesh mesh;
    const Vec3d ax = normalize(Vec3d{1, 0.3, 0.7});
    const double angle = 0.35, c = std::cos(angle), s = std::sin(angle);
    auto place = [&](double x, double z) {  // Rodrigues' rotation of (x, 0, z) about ax
        const Vec3d p{x, 0, z};
        const Vec3d k_cross_p = cross(ax, p);
        const double k_dot_p = dot(ax, p);
        const Vec3d r{p.x * c + k_cross_p.x * s + ax.x * k_dot_p * (1 - c),
                      p.y * c + k_cross_p.y * s + ax.y * k_dot_p * (1 - c),
                      p.z * c + k_cross_p.z * s + ax.z * k_dot_p * (1 - c)};
        return to_float(Vec3d{r.x * size + centre.x, r.y * size + centre.y, r.z * size + centre.z});
    };
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const double x0 = double(i) / n - 0.5, x1 = double(i + 1) / n - 0.5;
            const double z0 = double(j) / n - 0.5, z1 = double(j + 1) / n - 0.5;
            mesh.add_triangle(place(x0, z0), place(x1, z0), place(x1, z1));
            mesh.add_triangle(place(x0, z0), place(x1, z1), place(x0, z1));
        }
    return mesh;
}

TEST(ShadowRays, NoAcneOnATiltedFloorAtAnyScaleOrDistanceFromTheOrigin) {
    for (const auto& [size, centre] : {std::pair{1e-6f, Vec3{0, 0, 0}}, std::pair{1.0f, Vec3{0, 0, 0}},
                                       std::pair{1e6f, Vec3{0, 0, 0}}, std::pair{1.0f, Vec3{3000, -2000, 3000}},
                                       std::pair{1e-3f, Vec3{1, 1, 1}}}) {
        SCOPED_TRACE("floor " + std::to_string(size) + " across at " + std::to_string(centre.x));
        const Mesh mesh = tilted_floor(24, size, centre);
        const TriangleArray triangles = make_triangles(mesh);
        const Aabb bounds = mesh.bounds();
        // The light high above the floor's middle, on the side its normal (about +y) points to.
        const Vec3 up = normalize(cross(triangles[0].edge1, triangles[0].edge2));
        const Vec3 facing = up.y > 0 ? up : up * -1.0f;
        const Vec3 along = normalize(triangles[0].edge1);  // in the floor's plane
        const Camera camera(default_camera(bounds), 160, 120);
        // High above the middle, and grazing: 2 floor widths away, 3 degrees above the plane.
        for (const Vec3 offset : {facing * size, along * (2.0f * size) + facing * (0.105f * size)})
        for (AccelType type : {AccelType::Bvh, AccelType::Kd, AccelType::Grid}) {
            Lighting lighting;
            lighting.light = (bounds.lo + bounds.hi) * 0.5f + offset;
            lighting.shadows = true;
            AccelConfig config;
            config.type = type;
            auto accel = build_accelerator(mesh, config);
            ASSERT_TRUE(accel) << accel.error();
            const Frame frame = ray_cast(**accel, mesh, camera, {.threads = 1, .count_work = true, .lighting = &lighting});
            size_t floor = 0, dark = 0;
            for (int y = 0; y < camera.height(); ++y)
                for (int x = 0; x < camera.width(); ++x) {
                    const size_t i = frame.index(x, y);
                    if (frame.tri[i] == Hit::kNoHit) continue;
                    const Ray ray = camera.ray(x, y);
                    const Triangle& tri = triangles[frame.tri[i]];
                    if (!shadow_ray(tri, 0.3f, 0.3f, ray.dir, lighting.light)) continue;  // seen from below: unlit
                    ++floor;
                    // Lit: over the ambient 0.15 (by at least 0.85 sin 3 degrees); in shadow, exactly that.
                    dark += frame.colour.pixels[i] == point_light_shade(tri, Vec3{}, false) ? 1 : 0;
                }
            EXPECT_GT(floor, 1000u) << to_string(type);
            EXPECT_EQ(frame.shadow.rays, floor) << to_string(type);
            EXPECT_EQ(dark, 0u) << to_string(type) << ": the floor shadows itself";
            EXPECT_GT(frame.shadow.work.triangle_tests, 0u) << to_string(type);
        }
    }
}

TEST(ShadowRays, AnOccluderBetweenTheFloorAndTheLightDarkensTheFloorUnderIt) {
    Mesh mesh;
    mesh.add_triangle({-2, 0, -2}, {2, 0, -2}, {2, 0, 2});  // the floor, y = 0
    mesh.add_triangle({-2, 0, -2}, {2, 0, 2}, {-2, 0, 2});
    mesh.add_triangle({-0.5f, 1, -0.5f}, {0.5f, 1, -0.5f}, {0, 1, 0.5f});  // a small roof, y = 1
    const TriangleArray triangles = make_triangles(mesh);
    AccelConfig config;
    auto accel = build_accelerator(mesh, config);
    ASSERT_TRUE(accel) << accel.error();
    const Vec3 light{0, 3, 0};
    const Vec3 down{0, -1, 0};
    // Straight under the roof: blocked by it; at the floor's corner: lit.
    // Triangle 0 is (-2, 0, -2) + u (4, 0, 0) + v (4, 0, 4): (u, v) = (0.01, 0.5) is (0.04, 0, 0).
    auto under = shadow_ray(triangles[0], 0.01f, 0.5f, down, light);
    ASSERT_TRUE(under);
    EXPECT_NEAR(under->origin.x, 0.04f, 1e-6f);
    EXPECT_NEAR(under->origin.z, 0.0f, 1e-6f);
    EXPECT_TRUE((*accel)->intersect_any(*under));
    auto corner = shadow_ray(triangles[0], 0.9f, 0.05f, down, light);
    ASSERT_TRUE(corner);
    EXPECT_FALSE((*accel)->intersect_any(*corner));
    // The start lies off the floor on the viewer's (and the light's) side, by a hair.
    EXPECT_GT(under->origin.y, 0.0f);
    EXPECT_LT(under->origin.y, 1e-3f);
    // Seen from below, the floor's lit side faces away: no shadow ray, unlit.
    EXPECT_FALSE(shadow_ray(triangles[0], 0.01f, 0.5f, Vec3{0, 1, 0}, light));
}

TEST(ShadowRays, TheDefaultLightLightsAFlatScene) {
    // One triangle in z = 0: a light in its plane would light neither side.
    auto mesh = load_scene("builtin:single");
    ASSERT_TRUE(mesh) << mesh.error();
    const Vec3 light = default_light(mesh->bounds());
    EXPECT_GT(std::fabs(light.z), 0.1f);
    const TriangleArray triangles = make_triangles(*mesh);
    const Vec3 towards = Vec3{0, 0, light.z > 0 ? -1.0f : 1.0f};  // seen from the light's side
    EXPECT_TRUE(shadow_ray(triangles[0], 0.2f, 0.2f, towards, light));
}

TEST(Reflections, TheDirectionIsMirroredInThePlaneAndStartsOnTheViewersSide) {
    Mesh mesh;
    mesh.add_triangle({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});  // z = 0
    const TriangleArray triangles = make_triangles(mesh);
    const Vec3 in = normalize(Vec3{1, 2, -2});
    const Ray r = reflection_ray(triangles[0], 0.3f, 0.3f, in * 7.0f);
    EXPECT_NEAR(r.dir.x, in.x, 1e-6f);
    EXPECT_NEAR(r.dir.y, in.y, 1e-6f);
    EXPECT_NEAR(r.dir.z, -in.z, 1e-6f);
    EXPECT_GT(r.origin.z, 0.0f);  // the ray came from z > 0
    EXPECT_LT(r.origin.z, 1e-3f);
    EXPECT_EQ(r.t_min, 0.0f);
    EXPECT_EQ(r.t_max, kInfinity);
}

TEST(LitPicture, TheSameThroughEveryStructureWithShadowsAndReflections) {
    for (const std::string source : {"builtin:cornell-mirror", "builtin:teapot?n=6"}) {
        auto mesh = load_scene(source);
        ASSERT_TRUE(mesh) << mesh.error();
        auto lighting = Lighting{default_light(mesh->bounds()), true, true, mesh->mirror};
        const Camera camera(default_camera(mesh->bounds()), 200, 150);
        const Frame want = ray_cast(AcceleratorFor<BruteForce>(BruteForce(*mesh)), *mesh, camera,
                                    {.threads = 1, .count_work = true, .lighting = &lighting});
        EXPECT_GT(want.shadow.rays, 1000u) << source;
        if (source == "builtin:cornell-mirror") {
            EXPECT_GT(want.reflection.rays, 100u) << source;
            EXPECT_EQ(mesh->mirror.size(), mesh->triangle_count());
        } else {
            EXPECT_EQ(want.reflection.rays, 0u) << "the teapot has no mirrors";
        }
        // The light changes the picture (shadows, the mirror).
        const Frame headlight = ray_cast(AcceleratorFor<BruteForce>(BruteForce(*mesh)), *mesh, camera, {.threads = 1});
        EXPECT_NE(headlight.colour.pixels, want.colour.pixels);
        // The watertight test's answers are brute force's running the same test.
        const Frame want_watertight =
            ray_cast(AcceleratorFor<BruteForce>(BruteForce(*mesh, TriangleTestKind::Watertight)), *mesh, camera,
                     {.threads = 1, .lighting = &lighting});
        for (const auto& [label, config] : test::all_configurations()) {
            SCOPED_TRACE(label + " on " + source);
            auto accel = build_accelerator(*mesh, config);
            ASSERT_TRUE(accel) << accel.error();
            const Frame& oracle = config.triangle_test == TriangleTestKind::Watertight ? want_watertight : want;
            const Frame got = ray_cast(**accel, *mesh, camera, {.threads = 2, .lighting = &lighting});
            EXPECT_EQ(got.colour.pixels, oracle.colour.pixels);
            EXPECT_EQ(got.tri, oracle.tri);
            if (&oracle != &want) continue;
            const Frame counted = ray_cast(**accel, *mesh, camera, {.threads = 2, .count_work = true, .lighting = &lighting});
            EXPECT_EQ(counted.colour.pixels, want.colour.pixels) << "counting changes nothing";
            EXPECT_EQ(counted.shadow.rays, want.shadow.rays);
            EXPECT_EQ(counted.reflection.rays, want.reflection.rays);
        }
    }
}

TEST(LitPicture, AnyHitShadowRaysDoNoMoreWorkThanClosestHitOnTheSameSegments) {
    auto mesh = load_scene("builtin:teapot?n=8");
    ASSERT_TRUE(mesh) << mesh.error();
    const Lighting lighting{default_light(mesh->bounds()), true, false, {}};
    const Camera camera(default_camera(mesh->bounds()), 160, 120);
    for (AccelType type : {AccelType::Naive, AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree,
                           AccelType::Bsp}) {
        AccelConfig config;
        config.type = type;
        auto accel = build_accelerator(*mesh, config);
        ASSERT_TRUE(accel) << accel.error();
        const ShadowQueryWork w = measure_shadow_queries(**accel, *mesh, camera, lighting, 1);
        SCOPED_TRACE(to_string(type));
        EXPECT_GT(w.rays, 1000u);
        EXPECT_GT(w.blocked, 50u) << "the spout and handle shadow the body";
        EXPECT_EQ(w.disagreed, 0u);
        EXPECT_LT(w.any_hit_blocked.triangle_tests, w.closest_hit_blocked.triangle_tests);
        EXPECT_LE(w.any_hit.nodes_visited, w.closest_hit.nodes_visited);
        // Unblocked rays do the same work either way: the saving is all on blocked ones.
        EXPECT_EQ(w.any_hit.triangle_tests - w.any_hit_blocked.triangle_tests,
                  w.closest_hit.triangle_tests - w.closest_hit_blocked.triangle_tests);
    }
}

}  // namespace

namespace {

TEST(SteppedShadowRay, EveryStructureRecordsTheAnyHitQueryEndingWhereItStops) {
    auto mesh = load_scene("builtin:teapot?n=6");
    ASSERT_TRUE(mesh) << mesh.error();
    const std::vector<Ray> rays = shadow_segments(*mesh, 300, 21);
    const BruteForce brute(*mesh);
    for (AccelType type : {AccelType::Naive, AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree,
                           AccelType::Bsp}) {
        SCOPED_TRACE(to_string(type));
        AccelConfig config;
        config.type = type;
        auto accel = build_accelerator(*mesh, config);
        ASSERT_TRUE(accel) << accel.error();
        for (const Ray& ray : rays) {
            const SteppedRay stepped = record_ray(**accel, ray, StopAt::AnyHit);
            const bool blocked = brute.intersect_any(ray);
            ASSERT_EQ(stepped.hit.found(), blocked) << test::describe(ray);
            ASSERT_FALSE(stepped.events.empty());
            EXPECT_EQ(stepped.events.back().kind, EventKind::Done);
            if (!blocked) continue;
            // The walk stopped at the hit: the last triangle test is that hit, and the
            // named triangle really lies on the segment.
            auto last_test = std::find_if(stepped.events.rbegin(), stepped.events.rend(),
                                          [](const TraversalEvent& e) { return e.kind == EventKind::TriangleTest; });
            ASSERT_NE(last_test, stepped.events.rend());
            EXPECT_TRUE(last_test->hit);
            EXPECT_EQ(last_test->tri, stepped.hit.tri);
            EXPECT_GE(stepped.hit.t, ray.t_min);
            EXPECT_LE(stepped.hit.t, ray.t_max);
        }
    }
}

}  // namespace
