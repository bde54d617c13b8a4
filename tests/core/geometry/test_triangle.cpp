// Möller–Trumbore (lecture: 光线与三角形交叉 – 更快的算法): u, v, t, and the
// inside test u >= 0, v >= 0, u + v <= 1, with edge cases and no epsilons.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/geometry/triangle.h"
#include "core/util/random.h"

using namespace accelviz;

namespace {
// The right triangle (0,0,0), (1,0,0), (0,1,0) in the z = 0 plane.
const Triangle kTri = Triangle::from_points({0, 0, 0}, {1, 0, 0}, {0, 1, 0});

TriangleTest shoot_down_at(float x, float y) { return intersect_triangle(kTri, Ray{{x, y, 2}, {0, 0, -1}}); }
}  // namespace

TEST(MollerTrumbore, InteriorHitGivesBarycentricsAndDistance) {
    const TriangleTest r = shoot_down_at(0.25f, 0.5f);
    ASSERT_TRUE(r.hit);
    EXPECT_FLOAT_EQ(r.t, 2.0f);
    EXPECT_FLOAT_EQ(r.u, 0.25f);  // weight of p1 = (1,0,0)
    EXPECT_FLOAT_EQ(r.v, 0.5f);   // weight of p2 = (0,1,0)
}

TEST(MollerTrumbore, HitsOnEdgesAndVerticesCount) {
    EXPECT_TRUE(shoot_down_at(0.5f, 0.0f).hit);   // edge p0-p1 (v = 0)
    EXPECT_TRUE(shoot_down_at(0.0f, 0.5f).hit);   // edge p0-p2 (u = 0)
    EXPECT_TRUE(shoot_down_at(0.5f, 0.5f).hit);   // edge p1-p2 (u + v = 1)
    EXPECT_TRUE(shoot_down_at(0.0f, 0.0f).hit);   // vertex p0
    EXPECT_TRUE(shoot_down_at(1.0f, 0.0f).hit);   // vertex p1
    EXPECT_TRUE(shoot_down_at(0.0f, 1.0f).hit);   // vertex p2
}

TEST(MollerTrumbore, JustOutsideMisses) {
    EXPECT_FALSE(shoot_down_at(-1e-6f, 0.5f).hit);
    EXPECT_FALSE(shoot_down_at(0.5f, -1e-6f).hit);
    EXPECT_FALSE(shoot_down_at(0.5f + 1e-6f, 0.5f).hit);
    EXPECT_FALSE(shoot_down_at(2, 2).hit);
}

TEST(MollerTrumbore, BehindTheOriginMisses) {
    EXPECT_FALSE(intersect_triangle(kTri, Ray{{0.2f, 0.2f, -1}, {0, 0, -1}}).hit);
}

TEST(MollerTrumbore, RespectsTMax) {
    EXPECT_FALSE(intersect_triangle(kTri, Ray{{0.2f, 0.2f, 2}, {0, 0, -1}, 0, 1.5f}).hit);
    EXPECT_TRUE(intersect_triangle(kTri, Ray{{0.2f, 0.2f, 2}, {0, 0, -1}, 0, 2.0f}).hit);  // inclusive
}

TEST(MollerTrumbore, ParallelRayMisses) {
    EXPECT_FALSE(intersect_triangle(kTri, Ray{{0.2f, 0.2f, 0}, {1, 0, 0}}).hit);
    EXPECT_FALSE(intersect_triangle(kTri, Ray{{0.2f, 0.2f, 1}, {1, -0.0f, 0}}).hit);
}

TEST(MollerTrumbore, BothFacesAreHit) {
    const TriangleTest r = intersect_triangle(kTri, Ray{{0.2f, 0.2f, -3}, {0, 0, 1}});
    ASSERT_TRUE(r.hit);
    EXPECT_FLOAT_EQ(r.t, 3.0f);
}

TEST(MollerTrumbore, DegenerateTrianglesNeverHitAndNeverNaN) {
    const Triangle point = Triangle::from_points({0, 0, 0}, {0, 0, 0}, {0, 0, 0});
    const Triangle line = Triangle::from_points({0, 0, 0}, {1, 0, 0}, {2, 0, 0});
    for (const Triangle& tri : {point, line}) {
        EXPECT_FALSE(intersect_triangle(tri, Ray{{0.5f, 0, 1}, {0, 0, -1}}).hit);
        EXPECT_FALSE(intersect_triangle(tri, Ray{{0.5f, 1, 0}, {0, -1, 0}}).hit);
    }
}

TEST(MollerTrumbore, NoAbsoluteEpsilonTinyAndHugeTrianglesWork) {
    // A triangle 1e-4 across (det ~ 1e-8) and one 1e4 across: both must be hit.
    for (float scale : {1e-4f, 1.0f, 1e4f}) {
        const Triangle tri = Triangle::from_points({0, 0, 0}, {scale, 0, 0}, {0, scale, 0});
        const TriangleTest r = intersect_triangle(tri, Ray{{0.25f * scale, 0.25f * scale, scale}, {0, 0, -1}});
        EXPECT_TRUE(r.hit) << "scale " << scale;
        EXPECT_FLOAT_EQ(r.t, scale);
    }
}

TEST(MollerTrumbore, GrazingDirectionWithZeroComponents) {
    // Ray lying exactly along the edge direction in the plane: parallel, so a miss, not NaN.
    const TriangleTest r = intersect_triangle(kTri, Ray{{-1, 0, 0}, {1, 0, -0.0f}});
    EXPECT_FALSE(r.hit);
}

TEST(ClosestHitOrder, SmallerTThenSmallerId) {
    Hit best{5, 2.0f, 0, 0};
    EXPECT_TRUE(is_closer(1.0f, 9, best));
    EXPECT_TRUE(is_closer(2.0f, 4, best));
    EXPECT_FALSE(is_closer(2.0f, 6, best));
    EXPECT_FALSE(is_closer(3.0f, 0, best));
    EXPECT_TRUE(is_closer(kInfinity, 0, Hit{}));  // anything beats "no hit" at the same infinity, by id
}

// Found by fuzzing (tests/fuzz/corpus/obj/zero_area_hit_at_origin.obj): a zero-area
// triangle (two equal corners) whose det was rounding noise instead of 0 "hit" a ray
// at u = v = t = 0, at the ray's origin, far from the triangle. Brute force reported
// it and the grid (which never visits a cell at the origin) did not.
TEST(MollerTrumbore, AZeroAreaTriangleIsNeverHit) {
    const Vec3 a{0, 1, 0}, b{8, 0, 1};
    Ray ray;
    ray.origin = {0x1.1c2c88p+3f, -0x1.248864p+3f, 0x1.88736ep+2f};
    ray.dir = {-0x1.9a1af2p-2f, 0x1.95189ap-1f, -0x1.d9436ap-2f};
    EXPECT_TRUE(has_zero_area(a, b, b));
    EXPECT_FALSE(intersect_triangle(Triangle::from_points(a, b, b), ray).hit);
    // Collinear and coincident corners, and rays straight at them.
    const Vec3 m{4, 0.5f, 0.5f};
    EXPECT_TRUE(has_zero_area(a, m, b));
    EXPECT_TRUE(has_zero_area(a, a, a));
    EXPECT_FALSE(has_zero_area(a, b, Vec3{0, 0, 0}));
    Ray at_middle;
    at_middle.origin = m + Vec3{0, 0, -3};
    at_middle.dir = {0, 0, 1};
    EXPECT_FALSE(intersect_triangle(Triangle::from_points(a, m, b), at_middle).hit);
    EXPECT_FALSE(intersect_triangle(Triangle::from_points(a, a, a), at_middle).hit);
}

TEST(MollerTrumbore, EdgesParallelInFloatCountAsZeroArea) {
    // 1e-7 wide at one end, 33 long: in exact arithmetic a triangle, but p1 - p0 and
    // p2 - p0 round to the same float vector, so the test sees no area. It answered
    // u = v = 0 (a "hit" 14 units from the sliver, clamped into its box) before
    // from_points counted it as zero area (found by fuzzing the octree).
    const Vec3 p0{19, 27, 3}, p1{0, 0, 0}, p2{0, 0x1.ad7f2ap-24f, 0};
    EXPECT_FALSE(has_zero_area(p0, p1, p2));
    const Triangle tri = Triangle::from_points(p0, p1, p2);
    EXPECT_TRUE(std::isnan(tri.edge1.x));
    Ray ray;
    ray.origin = {0x1.d38ae6p+5f, 0x1.bda2ccp+3f, -0x1.d23634p+2f};
    ray.dir = {-0x1.f7edbp-1f, -0x1.18cc5ep-7f, 0x1.69caeep-3f};
    EXPECT_FALSE(intersect_triangle(tri, ray).hit);
    // The watertight test keeps the corners, and its edge functions see the sliver.
    EXPECT_FALSE(intersect_triangle(TriangleCorners::from_points(p0, p1, p2), ray).hit);
}

// The lecture's first way (plane, then the inside test): the same answers as
// Möller–Trumbore away from the edges, and each miss named by its edge.

TEST(PlaneFirst, AgreesWithMollerTrumboreAwayFromTheEdges) {
    Rng rng(5);
    int compared = 0, hits = 0;
    for (int i = 0; i < 20000; ++i) {
        auto point = [&](float r) { return Vec3{rng.uniform(-r, r), rng.uniform(-r, r), rng.uniform(-r, r)}; };
        const Vec3 p0 = point(1);
        const Triangle tri = Triangle::from_points(p0, p0 + point(1), p0 + point(1));
        // Aimed at the triangle's plane around it: about an eighth hit.
        const Vec3 origin = point(3);
        const Vec3 aim = p0 + tri.edge1 * rng.uniform(-0.5f, 1.5f) + tri.edge2 * rng.uniform(-0.5f, 1.5f);
        const Ray ray{origin, aim - origin};
        const TriangleTest mt = intersect_triangle(tri, ray);
        const PlaneFirstTest plane = plane_first_test(tri, ray);
        ASSERT_FALSE(plane.parallel);
        const float w = 1.0f - mt.u - mt.v;
        // Rounding decides rays within ~1e-4 of an edge differently in the two: skip those.
        if (std::fabs(mt.u) < 1e-4f || std::fabs(mt.v) < 1e-4f || std::fabs(w) < 1e-4f) continue;
        ++compared;
        EXPECT_EQ(plane.inside, mt.u >= 0 && mt.v >= 0 && w >= 0) << i;
        // Each edge's sign is its opposite corner's weight's sign.
        EXPECT_EQ(plane.edge[0] >= 0, mt.v >= 0) << i;
        EXPECT_EQ(plane.edge[1] >= 0, w >= 0) << i;
        EXPECT_EQ(plane.edge[2] >= 0, mt.u >= 0) << i;
        EXPECT_NEAR(plane.t, mt.t, 1e-3f * std::max(1.0f, std::fabs(mt.t))) << i;  // t = 1 at `aim`
        EXPECT_EQ(plane.hit, mt.hit) << i;
        hits += mt.hit;
    }
    EXPECT_GT(compared, 19000);
    EXPECT_GT(hits, 2000);
}

TEST(PlaneFirst, NamesTheEdgeARayMissesByAndSeesAParallelRay) {
    const PlaneFirstTest inside = plane_first_test(kTri, Ray{{0.25f, 0.25f, 2}, {0, 0, -1}});
    EXPECT_TRUE(inside.hit);
    EXPECT_FLOAT_EQ(inside.t, 2.0f);
    EXPECT_FLOAT_EQ(inside.point.x, 0.25f);
    // x < 0: beyond the edge p2 -> p0 (u < 0).
    const PlaneFirstTest u_negative = plane_first_test(kTri, Ray{{-0.2f, 0.5f, 2}, {0, 0, -1}});
    EXPECT_FALSE(u_negative.hit);
    EXPECT_LT(u_negative.edge[2], 0.0f);
    EXPECT_GT(u_negative.edge[0], 0.0f);
    EXPECT_GT(u_negative.edge[1], 0.0f);
    // x + y > 1: beyond the edge p1 -> p2 (u + v > 1).
    const PlaneFirstTest beyond = plane_first_test(kTri, Ray{{0.7f, 0.6f, 2}, {0, 0, -1}});
    EXPECT_FALSE(beyond.hit);
    EXPECT_LT(beyond.edge[1], 0.0f);
    EXPECT_GT(beyond.edge[0], 0.0f);
    EXPECT_GT(beyond.edge[2], 0.0f);
    const PlaneFirstTest parallel = plane_first_test(kTri, Ray{{-1, 0.3f, 0.5f}, {1, 0, 0}});
    EXPECT_TRUE(parallel.parallel);
    EXPECT_FALSE(parallel.hit);
}
