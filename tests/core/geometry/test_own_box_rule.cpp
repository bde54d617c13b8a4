// The ray–triangle test's own-box rule (intersect_triangle): a hit counts only if
// the ray meets the triangle's own box, and its t is brought into that box. It is
// what makes every structure agree with brute force on sliver triangles, where
// float Möller–Trumbore's u, v and t can be far off; on well-shaped triangles it
// must change nothing, not even for rays that graze them. And its companion for
// structures that store a triangle only where it lies: a candidate whose det is
// small beside its terms is solved again in double, so a hit lies on its triangle.
#include <gtest/gtest.h>

#include <algorithm>
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

/// The distance from x to the triangle a, b, c, in double, accurate for slivers too:
/// the nearest of the three edges, or the plane if x lies over the triangle. (Not
/// closest_point_on_triangle: its Voronoi-region tests take differences of products
/// of dot products, which lose all their bits on a sliver 2^-25 wide.) Each sign below
/// is wrong only within about 2^-50 of the triangle's size of a region's boundary,
/// where both answers agree that closely.
double distance_to_triangle(Vec3d x, Vec3d a, Vec3d b, Vec3d c) {
    auto to_segment = [&](Vec3d s, Vec3d e) {
        const Vec3d d = e - s;
        const double len2 = dot(d, d);
        const double t = len2 > 0 ? std::clamp(dot(x - s, d) / len2, 0.0, 1.0) : 0.0;
        const Vec3d q = s + d * t;
        return std::sqrt(dot(x - q, x - q));
    };
    double best = std::min({to_segment(a, b), to_segment(b, c), to_segment(c, a)});
    const Vec3d n = cross(b - a, c - a);  // corners' differences and their products: near exact
    const double n2 = dot(n, n);
    if (n2 > 0 && dot(cross(b - a, x - a), n) >= 0 && dot(cross(c - b, x - b), n) >= 0 &&
        dot(cross(a - c, x - c), n) >= 0)
        best = std::min(best, std::fabs(dot(x - a, n)) / std::sqrt(n2));
    return best;
}

/// The distance from `ray`'s point at t to the triangle p0, p1, p2, over the size it
/// is measured against: the point's distance from the origin plus the origin's
/// coordinates.
double off_triangle_share(Vec3d p0, Vec3d p1, Vec3d p2, const Ray& ray, float t) {
    const Vec3d o = to_double(ray.origin), d = to_double(ray.dir);
    const Vec3d x = o + d * double(t);
    const double size = std::sqrt(dot(x - o, x - o)) + std::fabs(o.x) + std::fabs(o.y) + std::fabs(o.z);
    return distance_to_triangle(x, p0, p1, p2) / size;
}

/// The same for Möller–Trumbore's form: the triangle as it sees it, p0, p0 + edge1,
/// p0 + edge2, exact in double.
double off_triangle_share(const Triangle& tri, const Ray& ray, float t) {
    const Vec3d p0 = to_double(tri.p0);
    return off_triangle_share(p0, p0 + to_double(tri.edge1), p0 + to_double(tri.edge2), ray, t);
}

TEST(IllConditionedHits, ASliversCandidateIsSolvedAgainInDouble) {
    // From the fuzzer: a sliver 2.4 long and 1e-7 wide, and a ray whose det is
    // rounding noise in float. Float Möller–Trumbore alone said inside, t = 4.3095,
    // a point 0.42 from the sliver but inside its box; the grid that stores the sliver
    // only in the cells it overlaps never tested it there. In double the ray meets the
    // sliver's plane at t = 4.82673, just beside the sliver as the test sees it.
    const Triangle sliver = Triangle::from_points({1, 1, 2}, {0, 1e-7f, 0}, {0, 0, 0});
    const Ray ray{{-0x1.0aaf82p+2f, 0x1.87c12cp-1f, -0x1.9f1ep-3f}, {0x1.ef0d76p-1f, -0x1.c20266p-5f, 0x1.fe4ecap-3f}};
    const TriangleTest test = intersect_triangle(sliver, ray);
    EXPECT_FALSE(test.hit);
    EXPECT_LT(test.u, 0.0f);
    EXPECT_NEAR(test.t, 4.82673f, 1e-4f);
}

/// Random slivers 1 to 2^11 long and down to 2^-25 of that wide, and rays from up
/// to 32 lengths away aimed at random points of their boxes or of the triangles: calls `check(a, b, c,
/// ray)` for each, which returns whether the test hit.
template <class Check>
int shoot_at_slivers(int count, Check check) {
    Rng rng(11);
    int hits = 0;
    for (int i = 0; i < count; ++i) {
        const float length = std::ldexp(1.0f, int(rng.below(12)));
        const float width = std::ldexp(length, -int(rng.below(26)));
        const Vec3 a = test::random_point_in(rng, {{-1, -1, -1}, {1, 1, 1}});
        const Vec3 along = test::random_direction(rng);
        const Vec3 b = a + along * length;
        const Vec3 c = a + along * (length * rng.uniform(0.0f, 1.0f)) + test::random_direction(rng) * width;
        Aabb box;
        for (Vec3 p : {a, b, c}) box.grow(p);
        Vec3 aim = test::random_point_in(rng, box);
        if (rng.below(2)) {  // or at a point of the triangle itself: most of these hit
            const float u = rng.uniform(0.0f, 1.0f), v = rng.uniform(0.0f, 1.0f - u);
            aim = a + (b - a) * u + (c - a) * v;
        }
        const Vec3 origin = aim - test::random_direction(rng) * (length * std::ldexp(1.0f, int(rng.below(6))));
        hits += check(a, b, c, Ray{origin, aim - origin}) ? 1 : 0;
    }
    return hits;
}

TEST(IllConditionedHits, EveryMollerTrumboreHitLiesOnItsTriangle) {
    // Float Möller–Trumbore alone put such hits up to a fifth of the ray's size off
    // the triangle; solved again in double where det is small beside its terms, every
    // hit lies within 2^-16 of it (the cell structures' padding: 2^-14 of the scene).
    const int hits = shoot_at_slivers(300000, [](Vec3 a, Vec3 b, Vec3 c, const Ray& ray) {
        const Triangle tri = Triangle::from_points(a, b, c);
        const TriangleTest test = intersect_triangle(tri, ray);
        if (test.hit) {
            EXPECT_LT(off_triangle_share(tri, ray, test.t), 0x1p-16);
        }
        return test.hit;
    });
    EXPECT_GT(hits, 5000);
}

TEST(IllConditionedHits, EveryWatertightHitLiesOnItsTriangle) {
    // The watertight test's signs are exact, but its t, a mean of the corners' depths
    // weighted by the edge functions, was up to 2^-14 of the ray's size off a sliver
    // until small sums of them were computed again in double.
    const int hits = shoot_at_slivers(300000, [](Vec3 a, Vec3 b, Vec3 c, const Ray& ray) {
        const TriangleTest test = intersect_triangle(TriangleCorners::from_points(a, b, c), ray);
        if (test.hit) {
            EXPECT_LT(off_triangle_share(to_double(a), to_double(b), to_double(c), ray, test.t), 0x1p-16);
        }
        return test.hit;
    });
    EXPECT_GT(hits, 5000);
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
