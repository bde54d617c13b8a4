// Four triangles per instruction sequence (triangle_lanes.h): every lane must give
// what intersect_triangle gives that triangle, bit for bit, in the SIMD lanes and in
// the plain loop, on well-shaped triangles, slivers, zero-area triangles and rays in
// a triangle's plane; lanes past a leaf's end must never count.
#include <gtest/gtest.h>

#include <bit>
#include <cmath>

#include "accel/accel_test_support.h"
#include "core/geometry/triangle_lanes.h"
#include "core/util/random.h"

namespace accelviz {
namespace {

uint32_t bits(float x) { return std::bit_cast<uint32_t>(x); }

/// A random triangle of one of four kinds: well shaped, a sliver, zero area (a corner
/// repeated), or one whose plane holds the ray's origin and direction.
Triangle random_triangle(Rng& rng, const Ray& ray) {
    const Vec3 a = test::random_point_in(rng, {{-2, -2, -2}, {2, 2, 2}});
    const Vec3 b = test::random_point_in(rng, {{-2, -2, -2}, {2, 2, 2}});
    switch (rng.below(4)) {
        case 0: return Triangle::from_points(a, b, test::random_point_in(rng, {{-2, -2, -2}, {2, 2, 2}}));
        case 1: return Triangle::from_points(a, b, a + (b - a) * 0.5f + Vec3{1e-6f, 0, 0});
        case 2: return Triangle::from_points(a, b, b);
        default: return Triangle::from_points(ray.origin, ray.origin + ray.dir * 3.0f, b);
    }
}

/// Every lane of `leaf` (count triangles from leaf-order index 0) against `ray`, as
/// the wide BVH's walk uses them: the first half in lanes, a candidate finished.
template <class Lanes>
void expect_lanes_match_the_one_triangle_test(const LeafTriangleLanes& lanes, const std::vector<Triangle>& tris,
                                              const Ray& ray) {
    const auto count = uint32_t(tris.size());
    const BoxTestRay box_ray(ray);
    for (uint32_t j = 0; j < count; j += 4) {
        const LaneTests test4 = moller_trumbore_lanes<Lanes>(lanes.leaf(0), count, j, ray);
        for (uint32_t i = 0; i < 4 && j + i < count; ++i) {
            const Triangle& tri = tris[j + i];
            const TriangleTest want = intersect_triangle(tri, ray, box_ray);
            TriangleTest got = test4.lane(int(i));
            if (test4.candidates >> i & 1) finish_moller_trumbore(lanes.get(0, count, j + i), ray, box_ray, got);
            else EXPECT_FALSE(want.hit);  // only candidates can hit
            ASSERT_EQ(got.hit, want.hit) << "triangle " << j + i;
            ASSERT_EQ(bits(got.t), bits(want.t)) << "triangle " << j + i;
            ASSERT_EQ(bits(got.u), bits(want.u)) << "triangle " << j + i;
            ASSERT_EQ(bits(got.v), bits(want.v)) << "triangle " << j + i;
            ASSERT_EQ(got.off_own_box, want.off_own_box) << "triangle " << j + i;
        }
    }
}

TEST(TriangleLanes, EveryLaneIsTheOneTriangleTestBitForBit) {
    Rng rng(41);
    int hits = 0;
    for (int leaf = 0; leaf < 20000; ++leaf) {
        Ray ray;
        ray.origin = test::random_point_in(rng, {{-4, -4, -4}, {4, 4, 4}});
        ray.dir = test::random_direction(rng);
        if (rng.below(4) == 0) ray.t_min = -kInfinity;  // rays that may hit behind their origin
        const auto count = uint32_t(1 + rng.below(9));  // 1 to 9 triangles: one to three groups of lanes
        std::vector<Triangle> tris;
        for (uint32_t k = 0; k < count; ++k) {
            tris.push_back(random_triangle(rng, ray));
            if (rng.below(3) == 0) {  // aim at it: a hit, or a graze of its edge
                const Vec3 p = tris.back().p0 + tris.back().edge1 * rng.uniform(0.0f, 1.0f);
                ray.dir = normalize(p - ray.origin);
            }
        }
        LeafTriangleLanes lanes;
        lanes.resize(count);
        for (uint32_t k = 0; k < count; ++k) lanes.set(0, count, k, tris[k]);
        for (uint32_t k = 0; k < count; ++k) {
            const Triangle back = lanes.get(0, count, k);
            for (int a = 0; a < 3; ++a) {
                ASSERT_EQ(bits(back.p0[a]), bits(tris[k].p0[a]));
                ASSERT_EQ(bits(back.edge1[a]), bits(tris[k].edge1[a]));
                ASSERT_EQ(bits(back.edge2[a]), bits(tris[k].edge2[a]));
            }
        }
        expect_lanes_match_the_one_triangle_test<ScalarLanes<4>>(lanes, tris, ray);
        expect_lanes_match_the_one_triangle_test<FastLanes<4>>(lanes, tris, ray);
        for (const Triangle& tri : tris) hits += intersect_triangle(tri, ray).hit;
    }
    EXPECT_GT(hits, 2000);  // the rays do hit: the comparison is not of misses only
}

TEST(TriangleLanes, LanesPastTheLeafsEndAreMaskedByTheCaller) {
    // A leaf of one triangle followed by a leaf whose triangle the ray hits: lanes 1-3
    // read the first leaf's other components and the next leaf's, whatever they say.
    const Triangle missed = Triangle::from_points({10, 10, 10}, {11, 10, 10}, {10, 11, 10});
    const Triangle hit = Triangle::from_points({-1, -1, 0}, {1, -1, 0}, {0, 1, 0});
    const Ray ray{{0, 0, -1}, {0, 0, 1}};
    LeafTriangleLanes lanes;
    lanes.resize(2);
    lanes.set(0, 1, 0, missed);
    lanes.set(1, 1, 0, hit);
    const LaneTests first = moller_trumbore_lanes<FastLanes<4>>(lanes.leaf(0), 1, 0, ray);
    EXPECT_EQ(first.candidates & 1u, 0u);
    const LaneTests second = moller_trumbore_lanes<FastLanes<4>>(lanes.leaf(1), 1, 0, ray);
    EXPECT_EQ(second.candidates & 1u, 1u);
    EXPECT_EQ(second.t[0], 1.0f);
}

}  // namespace
}  // namespace accelviz
