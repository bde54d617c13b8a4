// The closest-point query: the point-triangle distance against its regions, and the
// BVH and KD tree against brute force (the same triangle, the same distance, bit for
// bit) for seeded points near, on, inside and far from the tricky built-ins.
#include <gtest/gtest.h>

#include "core/accel/bvh_build.h"
#include "core/accel/kd_tree.h"
#include "core/geometry/scene.h"
#include "core/query/nearest_point.h"
#include "core/traversal/observers.h"
#include "core/util/random.h"
#include "test_support.h"

using namespace accelviz;

namespace {

void expect_near_point(Vec3d got, Vec3d want) {
    EXPECT_NEAR(got.x, want.x, 1e-12);
    EXPECT_NEAR(got.y, want.y, 1e-12);
    EXPECT_NEAR(got.z, want.z, 1e-12);
}

/// Seeded query points: random in the scene's box grown to three times its size,
/// every 7th corner exactly, every 5th centroid, and a few far away on each axis.
std::vector<Vec3d> query_points(const Mesh& mesh, int count, uint64_t seed) {
    Rng rng(seed);
    const Aabb box = mesh.bounds();
    const Vec3 c = box.center(), e = box.extent();
    std::vector<Vec3d> points;
    for (int i = 0; i < count; ++i) {
        const uint32_t tri = uint32_t(rng.next_u64() % std::max<size_t>(1, mesh.triangle_count()));
        if (i % 7 == 0 && mesh.triangle_count() > 0) {
            points.push_back(to_double(mesh.vertex(tri, i % 3)));
        } else if (i % 5 == 0 && mesh.triangle_count() > 0) {
            const Vec3d a = to_double(mesh.vertex(tri, 0)), b = to_double(mesh.vertex(tri, 1)),
                        d = to_double(mesh.vertex(tri, 2));
            points.push_back((a + b + d) * (1.0 / 3.0));
        } else {
            points.push_back({c.x + 1.5 * e.x * rng.uniform(-1.0f, 1.0f), c.y + 1.5 * e.y * rng.uniform(-1.0f, 1.0f),
                              c.z + 1.5 * e.z * rng.uniform(-1.0f, 1.0f)});
        }
    }
    for (int a = 0; a < 3; ++a) {
        Vec3d far = to_double(c);
        (a == 0 ? far.x : a == 1 ? far.y : far.z) += 100.0 * std::max({e.x, e.y, e.z, 1.0f});
        points.push_back(far);
    }
    return points;
}

void expect_same(const NearestPoint& got, const NearestPoint& want, Vec3d q) {
    EXPECT_EQ(got.tri, want.tri) << "at " << q.x << ", " << q.y << ", " << q.z;
    EXPECT_EQ(got.distance_squared, want.distance_squared) << "at " << q.x << ", " << q.y << ", " << q.z;
}

}  // namespace

TEST(NearestPoint, ClosestPointOnATriangleInEachRegion) {
    const Vec3d a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
    expect_near_point(closest_point_on_triangle({0.5, 0.5, 3}, a, b, c), {0.5, 0.5, 0});  // face
    expect_near_point(closest_point_on_triangle({-1, -1, 1}, a, b, c), a);                // vertex a
    expect_near_point(closest_point_on_triangle({3, -1, 0}, a, b, c), b);                 // vertex b
    expect_near_point(closest_point_on_triangle({-1, 3, 0}, a, b, c), c);                 // vertex c
    expect_near_point(closest_point_on_triangle({1, -2, 0}, a, b, c), {1, 0, 0});         // edge ab
    expect_near_point(closest_point_on_triangle({-2, 1, 0}, a, b, c), {0, 1, 0});         // edge ac
    expect_near_point(closest_point_on_triangle({2, 2, 0}, a, b, c), {1, 1, 0});          // edge bc
    // Degenerate: a segment, and a point.
    expect_near_point(closest_point_on_triangle({1, 1, 0}, a, b, {1, 0, 0}), {1, 0, 0});
    expect_near_point(closest_point_on_triangle({1, 1, 1}, b, b, b), b);
    expect_near_point(closest_point_on_triangle({5, 1, 0}, a, a, b), b);
}

TEST(NearestPoint, OnSliversTheNearestPointIsWhereItWasPlaced) {
    // Random slivers (float corners, 1 to 2^11 long, down to 2^-25 of that wide) and
    // points placed where the nearest point is known: off the face along the normal,
    // off an edge square to it, off a corner inside its cone. Fuzzing found a sliver on
    // which Ericson's region tests (products of dot products, their differences rounding
    // noise) returned a point 0.042 away for a point 1e-7 from the sliver.
    Rng rng(29);
    int checked = 0;
    for (int i = 0; i < 20000; ++i) {
        const double length = std::ldexp(1.0, int(rng.below(12)));
        const double width = std::ldexp(length, -int(rng.below(26)));
        const Vec3d along = normalize(Vec3d{rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)});
        const Vec3d side = normalize(cross(along, Vec3d{rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0), rng.uniform(-1.0, 1.0)}));
        const Vec3d start{rng.uniform(-4.0, 4.0), rng.uniform(-4.0, 4.0), rng.uniform(-4.0, 4.0)};
        auto as_float = [](Vec3d p) { return to_double(Vec3{float(p.x), float(p.y), float(p.z)}); };
        const Vec3d corner[3] = {as_float(start), as_float(start + along * length),
                                 as_float(start + along * (length * rng.uniform(0.0, 1.0)) + side * width)};
        const Vec3d n = cross(corner[1] - corner[0], corner[2] - corner[0]);
        if (!(dot(n, n) > 0)) continue;
        const Vec3d normal = normalize(n);
        const double h = length * rng.uniform(0.0, 2.0), k = length * rng.uniform(-2.0, 2.0);
        Vec3d on, p;
        switch (rng.below(3)) {
            case 0: {  // the face
                const double r1 = rng.uniform(0.0, 1.0), r2 = rng.uniform(0.0, 1.0 - r1);
                on = corner[0] + (corner[1] - corner[0]) * r1 + (corner[2] - corner[0]) * r2;
                p = on + normal * k;
                break;
            }
            case 1: {  // an edge, square to it in the plane, outwards, and along the normal
                const int e = int(rng.below(3));
                const Vec3d s = corner[e], t = corner[(e + 1) % 3], third = corner[(e + 2) % 3];
                on = s + (t - s) * rng.uniform(0.0, 1.0);
                Vec3d out = normalize(cross(t - s, normal));
                if (dot(out, third - s) > 0) out = out * -1.0;
                p = on + out * h + normal * k;
                break;
            }
            default: {  // a corner, inside its cone: away from both its edges
                const int v = int(rng.below(3));
                on = corner[v];
                const Vec3d u1 = normalize(corner[(v + 1) % 3] - on), u2 = normalize(corner[(v + 2) % 3] - on);
                p = on - (u1 + u2) * h + normal * k;
                break;
            }
        }
        const Vec3d got = closest_point_on_triangle(p, corner[0], corner[1], corner[2]);
        const Vec3d off = got - on;
        // The placement's own rounding: n's direction is good to about 2^-52 of the
        // sliver's length over its width (2^-27 at most here), times the offset.
        ASSERT_LE(std::sqrt(dot(off, off)), 1e-7 * (h + std::fabs(k) + length))
            << "sliver " << i << " (width/length 2^" << std::log2(width / length) << ")";
        ++checked;
    }
    EXPECT_GT(checked, 19000);
}

TEST(NearestPoint, BoxDistanceIsZeroInsideAndEuclideanOutside) {
    const Aabb box{{0, 0, 0}, {1, 2, 3}};
    EXPECT_EQ(box_distance_squared({0.5, 1, 1}, box), 0.0);
    EXPECT_EQ(box_distance_squared({2, 1, 1}, box), 1.0);
    EXPECT_EQ(box_distance_squared({-1, -2, 5}, box), 1.0 + 4.0 + 4.0);
}

TEST(NearestPoint, BvhAndKdTreeAnswerAsBruteForce) {
    for (const char* scene : {"builtin:teapot?n=4", "builtin:soup?n=600&seed=5", "builtin:same-centroid?n=120",
                              "builtin:same-box?n=80", "builtin:single", "builtin:twenty-two", "builtin:cornell",
                              "builtin:kd-challenge"}) {
        SCOPED_TRACE(scene);
        const Mesh mesh = *load_scene(scene);
        std::vector<Bvh> bvhs;
        for (BvhBuilder builder : {BvhBuilder::SahBinned, BvhBuilder::Median}) {
            BvhConfig config;
            config.builder = builder;
            bvhs.push_back(*build_bvh(mesh, config));
        }
        const KdTree kd = *build_kd_tree(mesh, KdConfig{});
        for (const Vec3d& q : query_points(mesh, 300, 11)) {
            NoObserver none;
            const NearestPoint want = nearest_point_brute_force(mesh, q, none);
            ASSERT_TRUE(want.found());
            for (const Bvh& bvh : bvhs) expect_same(nearest_point(bvh, mesh, q, none), want, q);
            expect_same(nearest_point(kd, mesh, q, none), want, q);
        }
    }
}

TEST(NearestPoint, OnAScannedMeshTheBvhAndKdTreeAnswerAsBruteForce) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = *load_scene(test::shared_asset("bunny.obj"));
    const Bvh bvh = *build_bvh(mesh, BvhConfig{});
    const KdTree kd = *build_kd_tree(mesh, KdConfig{});
    // Points near and on the scan's surface (its corners, centroids) and around it.
    for (const Vec3d& q : query_points(mesh, 120, 23)) {
        NoObserver none;
        const NearestPoint want = nearest_point_brute_force(mesh, q, none);
        expect_same(nearest_point(bvh, mesh, q, none), want, q);
        expect_same(nearest_point(kd, mesh, q, none), want, q);
    }
}

TEST(NearestPoint, PointsOnTheTeapotsSeamsWhereRoundingLeftTheTriangle) {
    // Found by fuzzing: the nearest point computed for triangle 95 (120) lay 3e-18
    // beyond its box's face at x = 0 (z = 0), nearer than the boxes around it, and the
    // BVH answered another triangle. Points just on or off the mesh near axis planes.
    const Mesh mesh = *load_scene("builtin:teapot?n=4");
    const Bvh bvh = *build_bvh(mesh, BvhConfig{});
    std::vector<Vec3d> points = {{3.1855800266323224e-18, 0.56610184879476821, 0.3728023019162392},
                                 {0.8510759960169012, 0.57540916249008101, 3.9147244815462832e-18}};
    Rng rng(5);
    for (int i = 0; i < 400; ++i) {
        const uint32_t tri = uint32_t(rng.next_u64() % mesh.triangle_count());
        const Vec3d p{rng.uniform(-1.0f, 1.0f), rng.uniform(0.0f, 0.8f), rng.uniform(-1.0f, 1.0f)};
        Vec3d on = closest_point_on_triangle(p, to_double(mesh.vertex(tri, 0)), to_double(mesh.vertex(tri, 1)),
                                             to_double(mesh.vertex(tri, 2)));
        (i % 2 ? on.x : on.z) *= 1e-17;  // pulled onto an axis plane, where the teapot's seams are
        points.push_back(on);
    }
    for (const Vec3d& q : points) {
        NoObserver none;
        expect_same(nearest_point(bvh, mesh, q, none), nearest_point_brute_force(mesh, q, none), q);
    }
}

TEST(NearestPoint, TheHierarchiesMeasureFewTrianglesAndReportWhatTheyDid) {
    const Mesh mesh = *load_scene("builtin:teapot");
    const Bvh bvh = *build_bvh(mesh, BvhConfig{});
    const KdTree kd = *build_kd_tree(mesh, KdConfig{});
    uint64_t bvh_tests = 0, kd_tests = 0;
    const std::vector<Vec3d> points = query_points(mesh, 100, 3);
    for (const Vec3d& q : points) {
        RecordingObserver bvh_events, kd_events;
        const NearestPoint b = nearest_point(bvh, mesh, q, bvh_events);
        const NearestPoint k = nearest_point(kd, mesh, q, kd_events);
        for (const auto* events : {&bvh_events.events, &kd_events.events}) {
            ASSERT_FALSE(events->empty());
            EXPECT_EQ(events->back().kind, EventKind::Done);
            EXPECT_EQ(events->back().tri, b.tri);
            EXPECT_EQ(events->back().t, float(b.distance()));
        }
        EXPECT_EQ(k.tri, b.tri);
        bvh_tests += bvh_events.counters().triangle_tests;
        kd_tests += kd_events.counters().triangle_tests;
    }
    // Brute force measures all 3,552 triangles for every point.
    EXPECT_LT(bvh_tests, points.size() * mesh.triangle_count() / 20);
    EXPECT_LT(kd_tests, points.size() * mesh.triangle_count() / 20);
}

TEST(NearestPoint, AnEmptySceneHasNoNearestPoint) {
    const Mesh mesh;
    NoObserver none;
    EXPECT_FALSE(nearest_point_brute_force(mesh, {0, 0, 0}, none).found());
    const Bvh bvh = *build_bvh(mesh, BvhConfig{});
    EXPECT_FALSE(nearest_point(bvh, mesh, {0, 0, 0}, none).found());
    const KdTree kd = *build_kd_tree(mesh, KdConfig{});
    EXPECT_FALSE(nearest_point(kd, mesh, {0, 0, 0}, none).found());
}
