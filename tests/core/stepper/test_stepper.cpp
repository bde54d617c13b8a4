// The stepper's model: slab and triangle inspectors against the recorded events,
// node boxes, the step's debug geometry, and the compare table.
#include <gtest/gtest.h>

#include <set>

#include "core/accel/brute_force.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/camera.h"
#include "core/stepper/stepper.h"
#include "test_support.h"

using namespace accelviz;

namespace {

std::shared_ptr<const Accelerator> build(const Mesh& mesh, AccelType type,
                                         BvhTraversal traversal = BvhTraversal::Ordered) {
    AccelConfig config;
    config.type = type;
    config.bvh_traversal = traversal;
    auto accel = build_accelerator(mesh, config);
    EXPECT_TRUE(accel) << accel.error();
    return *accel;
}

/// Camera rays over a small image of the scene's default view (some hit, some miss).
std::vector<Ray> camera_rays(const Mesh& mesh, int n) {
    const Camera camera(default_camera(mesh.bounds()), n, n);
    std::vector<Ray> rays;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) rays.push_back(camera.ray(x, y));
    return rays;
}

const Mesh& teapot() {
    static const Mesh mesh = *load_scene("builtin:teapot?n=4");
    return mesh;
}

}  // namespace

TEST(Stepper, SlabInspectorAgreesWithEveryRecordedBoxTest) {
    const Mesh& mesh = teapot();
    for (const AccelType type : {AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree, AccelType::Bsp}) {
        for (BvhTraversal traversal : {BvhTraversal::Ordered, BvhTraversal::Unordered}) {
            const auto accel = build(mesh, type, traversal);
            const NodeBoxes boxes(*accel);
            size_t checked = 0, hits = 0, misses = 0;
            std::vector<Ray> rays = camera_rays(mesh, 12);
            Ray behind = rays[70];  // a ray that may hit behind its origin: the BVH's other box test
            behind.t_min = -kInfinity;
            rays.push_back(behind);
            for (const Ray& ray : rays) {
                const SteppedRay r = record_ray(*accel, ray);
                for (const TraversalEvent& e : r.events) {
                    if (e.kind != EventKind::BoxTest) continue;
                    const auto s = inspect_box_test(r, boxes, e);
                    ASSERT_TRUE(s) << type << " node " << e.node;
                    EXPECT_TRUE(s->agrees) << type << " node " << e.node << ": " << s->t_enter << " vs " << e.t_enter
                                           << ", " << s->t_exit << " vs " << e.t_exit;
                    EXPECT_EQ(s->hit, e.hit);
                    EXPECT_FALSE(s->verdict.empty());
                    EXPECT_EQ(s->verdict.rfind(e.hit ? "hit" : "miss", 0), 0u) << s->verdict;
                    // The intersection is the max of the entries and the min of the exits (with the ray's range).
                    if (s->hit && ray.t_min >= 0) {
                        for (int a = 0; a < 3; ++a) {
                            if (!std::isnan(s->axis_min[a])) { EXPECT_LE(s->axis_min[a], s->t_enter); }
                            if (!std::isnan(s->axis_max[a])) { EXPECT_GE(s->axis_max[a], s->t_exit); }
                        }
                    }
                    ++checked;
                    (e.hit ? hits : misses)++;
                }
            }
            EXPECT_GT(checked, 100u) << type;
            EXPECT_GT(hits, 0u) << type;
            EXPECT_GT(misses, 0u) << type;
            if (type != AccelType::Bvh) break;  // one traversal only
        }
    }
}

TEST(Stepper, TriangleInspectorExplainsEachVerdict) {
    Mesh m;
    m.add_triangle({-1, -1, -2}, {1, -1, -2}, {0, 1, -2});  // 0: hit, farther
    m.add_triangle({-1, -1, -1}, {1, -1, -1}, {0, 1, -1});  // 1: hit, nearer
    m.add_triangle({5, 5, -3}, {6, 5, -3}, {5, 6, -3});     // 2: the plane is hit, outside the triangle
    m.add_triangle({-1, -1, -5}, {1, -1, -5}, {0, 1, -5});  // 3: inside but beyond the closest hit
    m.add_triangle({-1, 0, 0}, {1, 0, 0}, {0, 0, -1});      // 4: parallel to the ray? no: contains it
    const auto accel = build(m, AccelType::Naive);
    const SteppedRay r = record_ray(*accel, Ray{{0, 0, 0}, {0, 0, -1}});
    std::vector<TriangleInspection> tests;
    for (size_t i = 0; i < r.events.size(); ++i)
        if (r.events[i].kind == EventKind::TriangleTest) tests.push_back(inspect_triangle_test(r, i));
    ASSERT_EQ(tests.size(), 5u);
    EXPECT_TRUE(tests[0].hit);
    EXPECT_EQ(tests[0].verdict.rfind("hit", 0), 0u);
    EXPECT_FLOAT_EQ(tests[0].u + tests[0].v + tests[0].w, 1.0f);
    EXPECT_FLOAT_EQ(tests[0].t, 2.0f);
    EXPECT_TRUE(tests[1].hit);
    EXPECT_FLOAT_EQ(tests[1].t_max, 2.0f);  // tested against the closest so far: triangle 0
    EXPECT_FALSE(tests[2].hit);
    EXPECT_NE(tests[2].verdict.find("outside the triangle"), std::string::npos) << tests[2].verdict;
    EXPECT_FALSE(tests[3].hit);
    EXPECT_NE(tests[3].verdict.find("beyond the closest hit"), std::string::npos) << tests[3].verdict;
    EXPECT_FLOAT_EQ(tests[3].t_max, 1.0f);
    EXPECT_FALSE(tests[4].hit);
    EXPECT_NE(tests[4].verdict.find("parallel"), std::string::npos) << tests[4].verdict;
}

TEST(Stepper, TriangleInspectorNamesTheOwnBoxRule) {
    // A sliver that float Möller–Trumbore says the ray hits, though the ray passes
    // beside its box (test_own_box_rule.cpp): the inspector says why it is no hit.
    Mesh m;
    m.add_triangle({1, 16666, 1}, {5, 1, 0}, {0, 1, 1});
    const auto accel = build(m, AccelType::Naive);
    const SteppedRay r = record_ray(*accel, Ray{{0x1.e267ap+13f, -0x1.17e8dp+12f, -0x1.d2343cp+13f},
                                                {-0x1.685f4p-1f, 0x1.a2513cp-3f, 0x1.5c5672p-1f}});
    ASSERT_GE(r.events.size(), 1u);
    ASSERT_EQ(r.events[0].kind, EventKind::TriangleTest);
    const TriangleInspection test = inspect_triangle_test(r, 0);
    EXPECT_FALSE(test.hit);
    EXPECT_NE(test.verdict.find("own box"), std::string::npos) << test.verdict;
}

TEST(Stepper, NodeBoxesNestAndHoldTheirLeafIntervals) {
    const Mesh& mesh = teapot();
    for (const AccelType type : {AccelType::Bvh, AccelType::Kd, AccelType::Octree, AccelType::Bsp, AccelType::Grid}) {
        const auto accel = build(mesh, type);
        const NodeBoxes boxes(*accel);
        ASSERT_TRUE(boxes.root()) << type;
        size_t leaves = 0;
        for (const Ray& ray : camera_rays(mesh, 8)) {
            const SteppedRay r = record_ray(*accel, ray);
            for (const TraversalEvent& e : r.events) {
                if (e.kind != EventKind::Leaf && e.kind != EventKind::EnterCell) continue;
                const auto box = boxes.of(e);
                ASSERT_TRUE(box) << type;
                EXPECT_TRUE(boxes.root()->contains(*box)) << type;
                // The leaf's (or cell's) interval lies where the ray is inside its box (up to rounding).
                const Vec3 mid = ray.origin + ray.dir * (0.5f * (e.t_enter + e.t_exit));
                Aabb grown = *box;
                const Vec3 pad = boxes.root()->extent() * 1e-4f;
                grown.lo = grown.lo - pad;
                grown.hi = grown.hi + pad;
                EXPECT_TRUE(grown.contains(mid)) << type << " node " << e.node;
                ++leaves;
            }
        }
        EXPECT_GT(leaves, 10u) << type;
    }
}

TEST(Stepper, StepGeometryShowsStackCullsTrianglesAndTheClosestHit) {
    const Mesh& mesh = teapot();
    const auto accel = build(mesh, AccelType::Bvh);
    const NodeBoxes boxes(*accel);
    const Camera camera(default_camera(mesh.bounds()), 64, 64);
    const SteppedRay r = record_ray(*accel, camera.ray(32, 32));
    ASSERT_TRUE(r.hit.found());
    bool saw_stack = false, saw_cull = false;
    for (size_t k = 0; k <= r.events.size(); ++k) {
        const StepState s = replay(r.events, k);
        const DebugGeometry g = step_geometry(r, s, boxes, mesh);
        ASSERT_FALSE(g.segments.empty());  // the ray at least
        size_t stacked = 0, culled = 0;
        for (const DebugBox& b : g.boxes) {
            if (b.colour.b == kStepColours.stacked.b && b.colour.r == kStepColours.stacked.r) ++stacked;
            if (b.colour.r == kStepColours.culled_beyond.r && b.colour.g == kStepColours.culled_beyond.g) ++culled;
        }
        EXPECT_EQ(stacked, s.stack.size()) << k;
        size_t beyond = 0;
        for (const auto& c : s.culled) beyond += c.reason == CullReason::BeyondClosestHit;
        EXPECT_EQ(culled, beyond) << k;
        EXPECT_EQ(g.triangles.size(), s.tested.size()) << k;
        saw_stack |= stacked > 0;
        saw_cull |= culled > 0;
        const bool closest_label = std::any_of(g.labels.begin(), g.labels.end(), [](const DebugLabel& l) {
            return l.text.rfind("closest", 0) == 0;
        });
        EXPECT_EQ(closest_label, s.closest.found()) << k;
    }
    EXPECT_TRUE(saw_stack);
    EXPECT_TRUE(saw_cull);
}

TEST(Stepper, CompareTableOnTheBunnyCentreRay) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "bunny.obj not found";
    const auto mesh = load_obj(test::shared_asset("bunny.obj"));
    ASSERT_TRUE(mesh) << mesh.error();
    auto set = build_compare_set(*mesh);
    ASSERT_TRUE(set) << set.error();
    const Camera camera(default_camera(mesh->bounds()), 1280, 720);
    const std::vector<CompareRow> rows = compare_ray(*set, camera.ray(640, 360));
    ASSERT_EQ(rows.size(), 6u);
    EXPECT_EQ(rows[0].label, "naive");
    EXPECT_EQ(rows[0].counters.triangle_tests, mesh->triangle_count());
    ASSERT_TRUE(rows[0].hit.found());
    for (const CompareRow& row : rows) {
        EXPECT_TRUE(row.agrees_with_naive) << row.label;
        EXPECT_EQ(row.hit.tri, rows[0].hit.tri) << row.label;
        EXPECT_EQ(row.hit.t, rows[0].hit.t) << row.label;
    }
    const CompareRow& alg1 = rows[1];
    const CompareRow& alg2 = rows[2];
    EXPECT_NE(alg1.label.find("alg. 1"), std::string::npos);
    EXPECT_NE(alg2.label.find("alg. 2"), std::string::npos);
    EXPECT_LT(alg2.counters.nodes_visited, alg1.counters.nodes_visited);
    EXPECT_LT(alg2.counters.triangle_tests, alg1.counters.triangle_tests);
    std::printf("compare (bunny, pixel 640,360 of 1280x720):\n");
    for (const CompareRow& row : rows)
        std::printf("  %-24s nodes %6llu  boxes %6llu  tris %6llu  mailbox %4llu  tri %u t %.6g\n", row.label.c_str(),
                    (unsigned long long)row.counters.nodes_visited, (unsigned long long)row.counters.box_tests,
                    (unsigned long long)row.counters.triangle_tests, (unsigned long long)row.counters.mailbox_skips,
                    row.hit.tri, row.hit.t);
}

TEST(Stepper, TriangleInspectorComparesBothTestsWhereARaySlipsThrough) {
    // From inside an icosphere, aimed exactly at a vertex: Möller–Trumbore misses every
    // triangle around it (the ray leaves the closed mesh); the watertight test hits one.
    const auto sphere = load_scene("builtin:sphere?subdiv=2");
    ASSERT_TRUE(sphere) << sphere.error();
    const Ray ray{{0, 0.05f, 0}, Vec3{-0.525731087f, 0, -0.850650787f} - Vec3{0, 0.05f, 0}};
    for (TriangleTestKind kind : {TriangleTestKind::MollerTrumbore, TriangleTestKind::Watertight}) {
        AccelConfig config;
        config.type = AccelType::Bvh;
        config.triangle_test = kind;
        const auto accel = build_accelerator(*sphere, config);
        ASSERT_TRUE(accel) << accel.error();
        const SteppedRay r = record_ray(**accel, ray);
        EXPECT_EQ(r.triangle_test, kind);
        EXPECT_EQ(r.hit.found(), kind == TriangleTestKind::Watertight);
        size_t disagreements = 0;
        for (size_t i = 0; i < r.events.size(); ++i) {
            if (r.events[i].kind != EventKind::TriangleTest) continue;
            const TriangleInspection t = inspect_triangle_test(r, i);
            const TriangleTestComparison both = compare_triangle_tests(r, t, *sphere);
            // The test that ran is the one the event reports.
            EXPECT_EQ(kind == TriangleTestKind::Watertight ? both.watertight.hit : both.moller_trumbore.hit, t.hit);
            disagreements += both.disagree();
        }
        EXPECT_GE(disagreements, 1u);
    }
}

TEST(AxisAlignedPlanes, ABoxTestIsSixPlaneCrossingsCountedBothWays) {
    // The lecture's slide: x = x0 costs 1 subtraction and 1 division; N.x = c, in 3D,
    // 6 multiplications, 5 additions or subtractions and 1 division.
    EXPECT_EQ(kAxisPlaneOps.multiplies, 0);
    EXPECT_EQ(kAxisPlaneOps.adds, 1);
    EXPECT_EQ(kAxisPlaneOps.divides, 1);
    const BoxTestOps axis = box_test_ops(3, kAxisPlaneOps);
    EXPECT_EQ(axis.multiplies, 0);
    EXPECT_EQ(axis.adds, 18);
    EXPECT_EQ(axis.divides, 18);
    const BoxTestOps general = box_test_ops(3, kGeneralPlaneOps);
    EXPECT_EQ(general.multiplies, 108);
    EXPECT_EQ(general.adds, 90);
    EXPECT_EQ(general.divides, 18);
}
