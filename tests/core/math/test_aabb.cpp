// The slab test (lecture: 光线与轴对齐包围盒相交), including the cases where
// 1/d is ±inf and 0·inf would be NaN.
#include <gtest/gtest.h>

#include "core/math/aabb.h"

using namespace accelviz;

namespace {
const Aabb kUnitBox{{0, 0, 0}, {1, 1, 1}};

SlabResult test(Vec3 o, Vec3 d) { return slab_test(kUnitBox, RayPrecomp(Ray{o, d})); }
}  // namespace

TEST(SlabTest, StraightThroughAlongX) {
    const SlabResult r = test({-1, 0.5f, 0.5f}, {1, 0, 0});
    EXPECT_TRUE(r.hit());
    EXPECT_FLOAT_EQ(r.t_enter, 1.0f);
    EXPECT_FLOAT_EQ(r.t_exit, 2.0f);
}

TEST(SlabTest, OriginInsideGivesNegativeEnter) {
    const SlabResult r = test({0.5f, 0.5f, 0.5f}, {0, 0, 1});
    EXPECT_TRUE(r.hit());
    EXPECT_FLOAT_EQ(r.t_enter, -0.5f);
    EXPECT_FLOAT_EQ(r.t_exit, 0.5f);
}

TEST(SlabTest, BoxBehindTheRayIsMissed) {
    const SlabResult r = test({2, 0.5f, 0.5f}, {1, 0, 0});
    EXPECT_LT(r.t_exit, 0.0f);
    EXPECT_FALSE(r.hit());
}

TEST(SlabTest, ParallelRayOutsideSlabMisses) {
    // d.y = 0 and the origin is above the box: the y slab is empty.
    EXPECT_FALSE(test({-1, 2, 0.5f}, {1, 0, 0}).hit());
    EXPECT_FALSE(test({-1, -2, 0.5f}, {1, -0.0f, 0}).hit());
}

TEST(SlabTest, ParallelRayInsideSlabHits) {
    EXPECT_TRUE(test({-1, 0.5f, 0.5f}, {1, -0.0f, 0.0f}).hit());
}

TEST(SlabTest, OriginOnSlabPlaneWithZeroDirectionIsNotNaN) {
    // o.y == lo.y and d.y == +0: (lo - o) * inf = 0 * inf = NaN must not poison the test.
    for (float dy : {0.0f, -0.0f}) {
        for (float oy : {0.0f, 1.0f}) {
            const SlabResult r = test({-1, oy, 0.5f}, {1, dy, 0});
            EXPECT_TRUE(r.hit()) << "oy=" << oy << " dy=" << dy;
            EXPECT_FLOAT_EQ(r.t_enter, 1.0f);
            EXPECT_FLOAT_EQ(r.t_exit, 2.0f);
        }
    }
}

TEST(SlabTest, FlatBoxIsHitWhenCrossed) {
    const Aabb flat{{0, 0, 0}, {1, 0, 1}};  // zero extent in y: t_enter == t_exit
    const SlabResult r = slab_test(flat, RayPrecomp(Ray{{0.5f, 1, 0.5f}, {0, -1, 0}}));
    EXPECT_TRUE(r.hit());
    EXPECT_EQ(r.t_enter, r.t_exit);
}

TEST(SlabTest, DiagonalMiss) {
    // passes beside the box corner: the x and y intervals do not overlap (lecture's 2D example)
    EXPECT_FALSE(test({-1, 0.5f, 0.5f}, {1, 2, 0}).hit());
}

TEST(SlabTest, EmptyBoxIsNeverHit) {
    EXPECT_FALSE(slab_test(Aabb{}, RayPrecomp(Ray{{0, 0, 0}, {1, 1, 1}})).hit());
}
