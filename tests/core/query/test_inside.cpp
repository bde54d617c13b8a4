// Inside or outside a closed mesh by ray parity: the BVH counts every crossing
// brute force counts, and the vote is right on closed built-ins for seeded points
// well inside and well outside.
#include <gtest/gtest.h>

#include <cmath>

#include "core/accel/bvh_build.h"
#include "core/geometry/scene.h"
#include "core/query/inside.h"
#include "core/traversal/observers.h"
#include "core/util/random.h"
#include "test_support.h"

using namespace accelviz;

namespace {

std::vector<Vec3> seeded_points(int count, float half_width, uint64_t seed) {
    Rng rng(seed);
    std::vector<Vec3> points;
    for (int i = 0; i < count; ++i)
        points.push_back({rng.uniform(-half_width, half_width), rng.uniform(-half_width, half_width),
                          rng.uniform(-half_width, half_width)});
    return points;
}

}  // namespace

TEST(InsideByParity, TheDirectionsAreUnitAndOffTheAxes) {
    for (const Vec3& d : parity_directions()) {
        EXPECT_NEAR(std::sqrt(double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z), 1.0, 1e-6);
        for (float c : {d.x, d.y, d.z}) EXPECT_GT(std::abs(c), 0.1f);
    }
}

TEST(InsideByParity, TheBvhCountsEveryCrossingBruteForceCounts) {
    for (const char* scene : {"builtin:sphere", "builtin:cube", "builtin:teapot?n=3", "builtin:soup?n=300&seed=2"}) {
        SCOPED_TRACE(scene);
        const Mesh mesh = *load_scene(scene);
        const Bvh bvh = *build_bvh(mesh, BvhConfig{});
        const TriangleArray triangles = make_triangles(mesh);
        std::vector<Vec3> points = seeded_points(150, 2.0f, 7);
        for (uint32_t t = 0; t < mesh.triangle_count(); t += 5) points.push_back(mesh.vertex(t, 0));  // on the surface
        for (const Vec3& q : points)
            for (const Vec3& d : parity_directions()) {
                NoObserver none;
                const Ray ray{q, d, 0.0f, kInfinity};
                EXPECT_EQ(count_crossings(bvh, ray, none), count_crossings_brute_force(triangles, ray, none));
            }
    }
}

TEST(InsideByParity, OnAScannedMeshTheBvhCountsEveryCrossingBruteForceCounts) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = *load_scene(test::shared_asset("bunny.obj"));
    const Bvh bvh = *build_bvh(mesh, BvhConfig{});
    const TriangleArray triangles = make_triangles(mesh);
    const Aabb box = mesh.bounds();
    std::vector<Vec3> points;
    for (const Vec3& p : seeded_points(40, 1.0f, 19))  // in the scan's box
        points.push_back(box.center() + Vec3{p.x * box.extent().x, p.y * box.extent().y, p.z * box.extent().z} * 0.6f);
    for (uint32_t t = 0; t < mesh.triangle_count(); t += 4001) points.push_back(mesh.vertex(t, 0));  // on the surface
    for (const Vec3& q : points)
        for (const Vec3& d : parity_directions()) {
            NoObserver none;
            const Ray ray{q, d, 0.0f, kInfinity};
            EXPECT_EQ(count_crossings(bvh, ray, none), count_crossings_brute_force(triangles, ray, none));
        }
}

TEST(InsideByParity, PointsInAndOutClosedMeshesAreToldApart) {
    // The icosphere's faces are at least 0.95 from its centre, its corners at 1.
    const Mesh sphere = *load_scene("builtin:sphere");
    const Bvh sphere_bvh = *build_bvh(sphere, BvhConfig{});
    const Mesh cube = *load_scene("builtin:cube");
    const Bvh cube_bvh = *build_bvh(cube, BvhConfig{});
    int inside = 0, outside = 0;
    for (const Vec3& q : seeded_points(400, 1.6f, 3)) {
        NoObserver none;
        const float r = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
        const InsideTest s = inside_by_parity(q, [&](const Ray& ray) { return count_crossings(sphere_bvh, ray, none); });
        if (r < 0.94f) {
            EXPECT_TRUE(s.inside) << r;
            EXPECT_EQ(s.votes_inside, 3);
            ++inside;
        } else if (r > 1.01f) {
            EXPECT_FALSE(s.inside) << r;
            EXPECT_EQ(s.votes_inside, 0);
            ++outside;
        }
        const float m = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
        const InsideTest c = inside_by_parity(q, [&](const Ray& ray) { return count_crossings(cube_bvh, ray, none); });
        if (m < 0.99f) {
            EXPECT_TRUE(c.inside) << m;
        }
        if (m > 1.01f) {
            EXPECT_FALSE(c.inside) << m;
        }
    }
    EXPECT_GT(inside, 20);
    EXPECT_GT(outside, 100);
}

TEST(InsideByParity, EventsEndWithTheCount) {
    const Mesh mesh = *load_scene("builtin:cube");
    const Bvh bvh = *build_bvh(mesh, BvhConfig{});
    RecordingObserver events;
    const uint32_t n = count_crossings(bvh, Ray{{0, 0, 0}, parity_directions()[0], 0.0f, kInfinity}, events);
    EXPECT_EQ(n, 1u);  // from the centre, one face
    ASSERT_FALSE(events.events.empty());
    EXPECT_EQ(events.events.back().kind, EventKind::Done);
    EXPECT_EQ(events.events.back().count, 1u);
    EXPECT_TRUE(events.events.back().hit);  // odd: inside
}
