// The O(N) baseline against answers worked out by hand.
#include <gtest/gtest.h>

#include "core/accel/brute_force.h"
#include "core/geometry/scene.h"
#include "test_support.h"

using namespace accelviz;

namespace {
Hit closest(const BruteForce& bf, Vec3 o, Vec3 d) {
    NoObserver none;
    return bf.intersect_closest(Ray{o, d}, none);
}
}  // namespace

TEST(BruteForce, CubeFromOutsideHitsTheNearFace) {
    auto cube = load_scene("builtin:cube");
    ASSERT_TRUE(cube.ok()) << cube.error();
    const BruteForce bf(*cube);
    for (int axis = 0; axis < 3; ++axis)
        for (float sign : {-1.0f, 1.0f}) {
            Vec3 o{0.1f, 0.2f, 0.3f}, d{0, 0, 0};
            o[axis] = 5 * sign;
            d[axis] = -sign;
            const Hit h = closest(bf, o, d);
            ASSERT_TRUE(h.found());
            EXPECT_FLOAT_EQ(h.t, 4.0f) << "axis " << axis << " sign " << sign;  // face at ±1
        }
}

TEST(BruteForce, CubeFromInsideHitsTheFarFace) {
    auto cube = load_scene("builtin:cube");
    ASSERT_TRUE(cube.ok()) << cube.error();
    const Hit h = closest(BruteForce(*cube), {0, 0, 0}, {0, -1, 0});
    ASSERT_TRUE(h.found());
    EXPECT_FLOAT_EQ(h.t, 1.0f);
}

TEST(BruteForce, MissesAreMisses) {
    auto cube = load_scene("builtin:cube");
    ASSERT_TRUE(cube.ok()) << cube.error();
    const Hit h = closest(BruteForce(*cube), {0, 5, 0}, {0, 1, 0});
    EXPECT_FALSE(h.found());
    EXPECT_TRUE(std::isinf(h.t));
}

TEST(BruteForce, CountsOneTestPerTriangle) {
    auto cube = load_scene("builtin:cube");
    ASSERT_TRUE(cube.ok()) << cube.error();
    const BruteForce bf(*cube);
    CountingObserver counter;
    bf.intersect_closest(Ray{{0, 0, 5}, {0, 0, -1}}, counter);
    EXPECT_EQ(counter.counters.triangle_tests, cube->triangle_count());
    EXPECT_EQ(counter.counters.box_tests, 0u);
}

TEST(BruteForce, SharedEdgeTieGoesToTheSmallerId) {
    Mesh m;
    m.add_triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0});  // id 0
    m.add_triangle({1, 0, 0}, {1, 1, 0}, {0, 1, 0});  // id 1, shares the edge x + y = 1
    m.add_triangle({1, 0, 0}, {1, 1, 0}, {0, 1, 0});  // id 2, a duplicate of 1
    const BruteForce bf(m);
    EXPECT_EQ(closest(bf, {0.5f, 0.5f, 1}, {0, 0, -1}).tri, 0u);
    EXPECT_EQ(closest(bf, {0.8f, 0.8f, 1}, {0, 0, -1}).tri, 1u);
}

TEST(BruteForce, CornellBoxFloorAndCeiling) {
    if (!test::shared_asset_exists("cornellbox_original.obj")) GTEST_SKIP() << "shared assets missing";
    auto box = load_obj(test::shared_asset("cornellbox_original.obj"));
    ASSERT_TRUE(box.ok()) << box.error();
    const BruteForce bf(*box);
    // The floor is the plane y = 0 (README bounds: y from 0.0 to 1.99); shoot straight down
    // from a point beside the two blocks, and straight up to the ceiling at y = 1.99.
    const Hit down = closest(bf, {-0.8f, 1.0f, 0.8f}, {0, -1, 0});
    ASSERT_TRUE(down.found());
    EXPECT_NEAR(down.t, 1.0f, 1e-5);
    const Hit up = closest(bf, {-0.8f, 1.0f, 0.8f}, {0, 1, 0});
    ASSERT_TRUE(up.found());
    EXPECT_NEAR(up.t, 0.99f, 2e-3);
}
