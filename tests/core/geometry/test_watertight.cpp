// The watertight ray-triangle test (Woop, Benthin & Wald 2013) against Möller–Trumbore:
// from inside a closed mesh every ray must hit it. Counts the rays that slip through
// (leaks) with each test on a closed icosphere and a closed cube, for rays in random
// directions and rays aimed exactly at vertices and at points on shared edges (float
// inputs only: the aim is the float nearest the point). The watertight test must leak
// none; Möller–Trumbore leaks some (the counts are printed: docs/robustness.md).
#include <gtest/gtest.h>

#include <cstdio>

#include "accel/accel_test_support.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"

using namespace accelviz;

namespace {

constexpr size_t kRays = test::rays_for_this_build(100'000);

enum class Aim { RandomDirection, Vertex, SharedEdge };

/// Rays from points inside the mesh (|x|, |y|, |z| < `inside`), of one kind.
std::vector<Ray> rays_from_inside(const Mesh& mesh, Aim aim, float inside, uint64_t seed) {
    Rng rng(seed);
    std::vector<Ray> rays(kRays);
    for (Ray& ray : rays) {
        ray.origin = {rng.uniform(-inside, inside), rng.uniform(-inside, inside), rng.uniform(-inside, inside)};
        const size_t tri = size_t(rng.next_u64() % mesh.triangle_count());
        const int corner = int(rng.next_u64() % 3);
        const Vec3 a = mesh.vertex(tri, corner), b = mesh.vertex(tri, (corner + 1) % 3);
        switch (aim) {
            case Aim::RandomDirection: ray.dir = test::random_direction(rng); break;
            case Aim::Vertex: ray.dir = a - ray.origin; break;
            case Aim::SharedEdge: ray.dir = a + (b - a) * rng.uniform(0.0f, 1.0f) - ray.origin; break;
        }
    }
    return rays;
}

/// Rays that hit nothing, through `test` in a BVH (which answers as brute force does).
size_t leaks(const Mesh& mesh, const std::vector<Ray>& rays, TriangleTestKind test) {
    AccelConfig config;
    config.type = AccelType::Bvh;
    config.triangle_test = test;
    const auto bvh = build_accelerator(mesh, config);
    EXPECT_TRUE(bvh) << bvh.error();
    size_t missed = 0;
    for (const Ray& ray : rays) missed += !(*bvh)->intersect_closest(ray).found();
    return missed;
}

void check_closed(const std::string& scene, float inside, uint64_t seed) {
    const auto mesh = load_scene(scene);
    ASSERT_TRUE(mesh) << mesh.error();
    size_t mt_total = 0;
    for (Aim aim : {Aim::RandomDirection, Aim::Vertex, Aim::SharedEdge}) {
        const char* name = aim == Aim::RandomDirection ? "random directions" : aim == Aim::Vertex ? "at vertices" : "at shared edges";
        const std::vector<Ray> rays = rays_from_inside(*mesh, aim, inside, seed + uint64_t(aim));
        const size_t mt = leaks(*mesh, rays, TriangleTestKind::MollerTrumbore);
        const size_t watertight = leaks(*mesh, rays, TriangleTestKind::Watertight);
        std::printf("[ leaks    ] %s, %zu rays %s: Moller-Trumbore %zu, watertight %zu\n", scene.c_str(), rays.size(),
                    name, mt, watertight);
        EXPECT_EQ(watertight, 0u) << scene << ", " << name;
        mt_total += mt;
    }
    ::testing::Test::RecordProperty("moller_trumbore_leaks", int(mt_total));
    EXPECT_GT(mt_total, 0u) << "the lesson: Moller-Trumbore lets rays through shared edges and vertices";
}

}  // namespace

TEST(Watertight, NoRayLeavesAClosedIcosphere) { check_closed("builtin:sphere?subdiv=4", 0.5f, 11); }
TEST(Watertight, NoRayLeavesAClosedCube) { check_closed("builtin:cube", 0.9f, 21); }

TEST(Watertight, AgreesWithMollerTrumboreAwayFromEdges) {
    // The right triangle (0,0,0), (1,0,0), (0,1,0); rays straight down at interior points.
    const Vec3 p0{0, 0, 0}, p1{1, 0, 0}, p2{0, 1, 0};
    const TriangleCorners corners = TriangleCorners::from_points(p0, p1, p2);
    for (auto [x, y] : {std::pair{0.25f, 0.25f}, {0.1f, 0.7f}, {0.6f, 0.3f}}) {
        const Ray ray{{x, y, 2}, {0, 0, -1}};
        const TriangleTest w = intersect_triangle(corners, ray);
        const TriangleTest m = intersect_triangle(Triangle::from_points(p0, p1, p2), ray);
        ASSERT_TRUE(w.hit && m.hit);
        EXPECT_FLOAT_EQ(w.t, 2.0f);
        EXPECT_FLOAT_EQ(w.u, m.u);  // the weight of p1 = x
        EXPECT_FLOAT_EQ(w.v, m.v);  // the weight of p2 = y
    }
    // Outside, behind, parallel, and a zero-area triangle: no hit.
    EXPECT_FALSE(intersect_triangle(corners, Ray{{0.6f, 0.6f, 2}, {0, 0, -1}}).hit);
    EXPECT_FALSE(intersect_triangle(corners, Ray{{0.2f, 0.2f, -2}, {0, 0, -1}}).hit);
    EXPECT_FALSE(intersect_triangle(corners, Ray{{0.2f, 0.2f, 0}, {1, 0, 0}}).hit);
    EXPECT_FALSE(intersect_triangle(TriangleCorners::from_points(p0, p1, p1), Ray{{0.2f, 0, 2}, {0, 0, -1}}).hit);
    // Both faces, and edges and corners count (a closed triangle).
    EXPECT_TRUE(intersect_triangle(corners, Ray{{0.2f, 0.2f, -2}, {0, 0, 1}}).hit);
    EXPECT_TRUE(intersect_triangle(corners, Ray{{0.5f, 0.5f, 2}, {0, 0, -1}}).hit);
    EXPECT_TRUE(intersect_triangle(corners, Ray{{1, 0, 2}, {0, 0, -1}}).hit);
}

TEST(Watertight, EveryStructureAgreesWithWatertightBruteForce) {
    // The same exactness the Möller–Trumbore oracle tests ask for: the triangle and
    // bit-identical t, u, v of brute force with the same test, for every structure.
    for (const char* scene : {"builtin:teapot?n=4", "builtin:same-box?n=200", "builtin:stadium?n=4"}) {
        const auto mesh = load_scene(scene);
        ASSERT_TRUE(mesh) << mesh.error();
        const std::vector<Ray> rays = test::make_test_rays(*mesh, 20'000, 31);
        const std::vector<Hit> want = test::brute_force_answers(*mesh, rays, TriangleTestKind::Watertight);
        const BruteForce brute(*mesh, TriangleTestKind::Watertight);
        for (size_t i = 0; i < rays.size(); i += 101) {
            NoObserver none;
            ASSERT_TRUE(test::same_hit(brute.intersect_closest(rays[i], none), want[i])) << test::describe(rays[i]);
        }
        for (const auto& [label, config] : test::all_configurations()) {
            if (config.triangle_test != TriangleTestKind::Watertight) continue;
            const auto built = build_accelerator(*mesh, config);
            ASSERT_TRUE(built) << built.error();
            size_t wrong = 0;
            for (size_t i = 0; i < rays.size(); ++i) {
                const Hit got = (*built)->intersect_closest(rays[i]);
                if (test::same_hit(got, want[i]) && (*built)->intersect_any(rays[i]) == want[i].found()) continue;
                if (wrong++ < 3)
                    ADD_FAILURE() << label << " on " << scene << ": " << test::describe(rays[i]) << ": got "
                                  << test::describe(got) << ", brute force " << test::describe(want[i]);
            }
            EXPECT_EQ(wrong, 0u) << label << " on " << scene;
        }
    }
}
