// The ray–triangle test's own-box rule (intersect_triangle): a hit counts only if
// the ray meets the triangle's own box, and its t is brought into that box. It is
// what makes every structure agree with brute force on sliver triangles, where
// float Möller–Trumbore's u, v and t can be far off; on well-shaped triangles it
// must change nothing, not even for rays that graze them.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "accel/accel_test_support.h"
#include "core/geometry/scene.h"
#include "core/util/random.h"

namespace accelviz {
namespace {

// From the fuzzer: a sliver 16665 long and about 5 wide, and a ray that passes
// beside its box. Float Möller–Trumbore says u = v = 0.5, a hit.
const Triangle kSliver = Triangle::from_points({1, 16666, 1}, {5, 1, 0}, {0, 1, 1});
const Ray kBesideTheSliver{{0x1.e267ap+13f, -0x1.17e8dp+12f, -0x1.d2343cp+13f},
                           {-0x1.685f4p-1f, 0x1.a2513cp-3f, 0x1.5c5672p-1f}};

TEST(OwnBoxRule, AHitOnARayThatMissesTheTrianglesBoxIsNoHit) {
    // The exact slab test agrees: the ray misses the box, so it cannot hit the triangle.
    const SlabResult exact = slab_test(kSliver.box(), RayPrecomp(kBesideTheSliver));
    EXPECT_GT(exact.t_enter, exact.t_exit);
    const TriangleTest test = intersect_triangle(kSliver, kBesideTheSliver);
    EXPECT_FALSE(test.hit);
    EXPECT_TRUE(test.off_own_box);
    EXPECT_GE(test.u, 0.0f);  // what Möller–Trumbore alone says: inside
    EXPECT_GE(test.v, 0.0f);
    EXPECT_LE(test.u + test.v, 1.0f);
}

TEST(OwnBoxRule, EveryHitLiesInItsTrianglesWidenedBox) {
    // Slivers 1 wide and 1 to 2^39 long, rays aimed exactly at their far corners
    // from all sides: Möller–Trumbore alone puts 7 of these hits outside the box.
    Rng rng(42);
    int hits = 0;
    for (int i = 0; i < 20000; ++i) {
        const float length = std::ldexp(1.0f, int(rng.below(40)));
        const Vec3 a = test::random_point_in(rng, {{-1, -1, -1}, {1, 1, 1}});
        const Vec3 b = a + test::random_direction(rng) * length;
        const Vec3 c = a + test::random_direction(rng);
        const Triangle tri = Triangle::from_points(a, b, c);
        const Vec3 aim = rng.below(2) ? b : c;
        const Vec3 origin = aim - test::random_direction(rng) * (length * 2.0f);
        const Ray ray{origin, aim - origin};
        const TriangleTest test = intersect_triangle(tri, ray);
        if (!test.hit) continue;
        ++hits;
        const SlabResult own = widened_slab_test<false>(tri.box(), BoxTestRay(ray), -kInfinity, kInfinity);
        ASSERT_LE(own.t_enter, test.t) << "triangle " << i;
        ASSERT_GE(own.t_exit, test.t) << "triangle " << i;
    }
    EXPECT_GT(hits, 1000);
}

TEST(OwnBoxRule, GrazingRaysStillHitAFloor) {
    // A floor 2000 units square seen from 1 unit above it: the far rays meet it at
    // under 0.06 degrees, where Möller–Trumbore's t is least accurate. The rule must
    // not punch holes: every ray aimed inside a floor triangle hits it, at a t within
    // a relative 1e-5 of the exact distance (z = 0 reached at t = 1 along o -> aim).
    const Triangle floor_a = Triangle::from_points({-1000, -1000, 0}, {1000, -1000, 0}, {1000, 1000, 0});
    const Triangle floor_b = Triangle::from_points({-1000, -1000, 0}, {1000, 1000, 0}, {-1000, 1000, 0});
    Rng rng(7);
    for (int i = 0; i < 100000; ++i) {
        const Vec3 origin{0, 0, 1};
        const Vec3 aim = test::random_point_in(rng, {{-999, -999, 0}, {999, 999, 0}});
        const Ray ray{origin, aim - origin};
        const TriangleTest a = intersect_triangle(floor_a, ray), b = intersect_triangle(floor_b, ray);
        ASSERT_TRUE(a.hit || b.hit) << "ray " << i << " slipped through the floor at " << aim.x << ", " << aim.y;
        const float t = a.hit ? a.t : b.t;
        ASSERT_NEAR(t, 1.0f, 1e-5f) << "ray " << i;
    }
}

// Every OBJ in the fuzzer's seed corpus (among them each input that once made a
// structure disagree with brute force), replayed with the fuzzer's own rays.
TEST(OwnBoxRule, FuzzCorpusAgreesWithBruteForce) {
    int files = 0;
    for (const auto& entry : std::filesystem::directory_iterator(ACCELVIZ_OBJ_CORPUS)) {
        std::ifstream in(entry.path(), std::ios::binary);
        std::stringstream text;
        text << in.rdbuf();
        const std::string bytes = text.str();
        auto mesh = parse_obj(bytes, entry.path().filename().string());
        if (!mesh) continue;  // a seed of bad input: refusing it is the right answer
        ++files;
        const auto wrong = test::first_disagreement(*mesh, test::fuzz_rays(*mesh, bytes.size()));
        EXPECT_FALSE(wrong) << entry.path().filename() << ": " << *wrong;
    }
    EXPECT_GE(files, 7);
}

}  // namespace
}  // namespace accelviz
