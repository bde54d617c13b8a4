// A refitted BVH (built at one time of a moving scene, its boxes recomputed for
// another) returns exactly what brute force returns on the moved mesh, by both
// traversals and any-hit; refitting to the mesh it was built over gives the built
// boxes bit for bit; refitting on 1 and 2 threads gives the same tree; a refit
// tree's SAH cost grows under a wave and not under a rigid motion; the moving
// built-in scenes keep their triangles from one time to the next.
#include <gtest/gtest.h>

#include <bit>

#include <tbb/global_control.h>

#include "accel/accel_test_support.h"
#include "core/accel/bvh_build.h"
#include "core/geometry/scene.h"
#include "test_support.h"

using namespace accelviz;
using namespace accelviz::test;

namespace {

Mesh scene(const std::string& source) {
    auto mesh = load_scene(source);
    EXPECT_TRUE(mesh.ok()) << source << ": " << mesh.error();
    return mesh.ok() ? *mesh : Mesh{};
}

bool same_box(const Aabb& a, const Aabb& b) {
    auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
    return bits(a.lo.x) == bits(b.lo.x) && bits(a.lo.y) == bits(b.lo.y) && bits(a.lo.z) == bits(b.lo.z) &&
           bits(a.hi.x) == bits(b.hi.x) && bits(a.hi.y) == bits(b.hi.y) && bits(a.hi.z) == bits(b.hi.z);
}

/// Builds over `before`, refits to `after` and checks rays against brute force on `after`.
void check_refit(const Mesh& before, const Mesh& after, size_t ray_count, uint64_t seed,
                 TriangleTestKind test = TriangleTestKind::MollerTrumbore) {
    SCOPED_TRACE(before.name + " refitted to " + after.name);
    Bvh bvh = *build_bvh(before, {});
    bvh.triangle_test = test;
    ASSERT_FALSE(refit_bvh(bvh, after).has_value());
    EXPECT_GT(bvh.build_stats.refit_ms, 0.0);
    const std::vector<Ray> rays = make_test_rays(after, ray_count, seed);
    const std::vector<Hit> expected = brute_force_answers(after, rays, test);
    Bvh unordered = bvh;
    unordered.traversal = BvhTraversal::Unordered;
    int failures = 0;
    for (size_t i = 0; i < rays.size() && failures < 8; ++i) {
        NoObserver none;
        const Hit closest = bvh.intersect_closest(rays[i], none);
        const Hit lecture = unordered.intersect_closest(rays[i], none);
        const bool any = bvh.intersect_any(rays[i]);
        if (!same_hit(closest, expected[i]) || !same_hit(lecture, expected[i]) || any != expected[i].found()) {
            ++failures;
            ADD_FAILURE() << "refitted: " << describe(closest) << " / " << describe(lecture) << " / any " << any
                          << ", brute force: " << describe(expected[i]) << " for " << describe(rays[i]);
        }
    }
}

/// Every box of a refitted tree is exactly its contents' box: a leaf's the union of
/// its triangles' boxes (triangle_box, as the build makes them), an interior node's
/// the union of its children's.
void expect_tight_boxes(const Bvh& bvh, const Mesh& mesh) {
    for (size_t n = 0; n < bvh.nodes.size(); ++n) {
        const BvhNode& node = bvh.nodes[n];
        Aabb box;
        if (node.is_leaf()) {
            for (uint32_t k = node.first; k < node.first + node.count; ++k) box.grow(mesh.triangle_bounds(bvh.prim_ids[k]));
        } else {
            box = bvh.nodes[node.first].bounds;
            box.grow(bvh.nodes[node.first + 1].bounds);
        }
        ASSERT_TRUE(same_box(box, node.bounds)) << "node " << n << " of " << mesh.name;
    }
}

TEST(BvhRefit, ToTheSameMeshGivesTheBuiltBoxes) {
    for (const char* source : {"builtin:teapot", "builtin:same-box", "builtin:cornell", "builtin:moving?t=0.3"}) {
        SCOPED_TRACE(source);
        const Mesh mesh = scene(source);
        const Bvh built = *build_bvh(mesh, {});
        Bvh refitted = built;
        ASSERT_FALSE(refit_bvh(refitted, mesh).has_value());
        gather_refit_stats(refitted);
        ASSERT_EQ(refitted.nodes.size(), built.nodes.size());
        for (size_t n = 0; n < built.nodes.size(); ++n)
            ASSERT_TRUE(same_box(refitted.nodes[n].bounds, built.nodes[n].bounds)) << "node " << n;
        EXPECT_EQ(refitted.build_stats.sah_cost, built.build_stats.sah_cost);
        EXPECT_EQ(refitted.build_stats.leaves, built.build_stats.leaves);
        EXPECT_EQ(refitted.build_stats.leaf_size_histogram, built.build_stats.leaf_size_histogram);
    }
}

TEST(BvhRefit, TeapotFlyingRoundTheRoomMatchesBruteForce) {
    const Mesh start = scene("builtin:moving?t=0&n=6");
    for (const char* later : {"builtin:moving?t=0.125&n=6", "builtin:moving?t=0.5&n=6", "builtin:moving?t=3.7&n=6"})
        check_refit(start, scene(later), 20'000, 31);
    check_refit(start, scene("builtin:moving?t=0.5&n=6"), 5'000, 32, TriangleTestKind::Watertight);
}

TEST(BvhRefit, WaveOverTheTeapotMatchesBruteForce) {
    const Mesh start = scene("builtin:wave?mesh=builtin:teapot&t=0");
    check_refit(start, scene("builtin:wave?mesh=builtin:teapot&t=0.4&height=0.05"), 20'000, 33);
    // A different amplitude is a different motion of the same triangles.
    check_refit(start, scene("builtin:wave?mesh=builtin:teapot&t=0.9&height=0.5"), 20'000, 34);
}

TEST(BvhRefit, WaveOverTheBunnyMatchesBruteForce) {
    if (!shared_asset_exists("bunny.obj")) GTEST_SKIP() << "the shared bunny is not here";
    const std::string bunny = shared_asset("bunny.obj");
    check_refit(scene("builtin:wave?mesh=" + bunny + "&t=0"), scene("builtin:wave?mesh=" + bunny + "&t=0.3"), 20'000,
                35);
}

/// The SAH cost of a tree built over `start` and refitted to `later`, and of one built over `later`.
std::pair<double, double> refit_and_rebuild_cost(const std::string& start, const std::string& later) {
    Bvh refitted = *build_bvh(scene(start), {});
    const Mesh moved = scene(later);
    EXPECT_FALSE(refit_bvh(refitted, moved).has_value());
    gather_refit_stats(refitted);
    EXPECT_NE(refitted.build_stats.notes.back().find("refitted"), std::string::npos);
    return {refitted.build_stats.sah_cost, build_bvh(moved, {})->build_stats.sah_cost};
}

// A deforming mesh: the refitted tree's quality decays as the wave travels (its
// splits were chosen for other positions), while a rebuild stays as good.
TEST(BvhRefit, UnderAWaveTheRefitTreeDecays) {
    const std::string sphere = "builtin:wave?mesh=builtin:sphere?subdiv=5&height=0.2";
    const auto [early_refit, early_rebuild] = refit_and_rebuild_cost(sphere + "&t=0", sphere + "&t=0.125");
    const auto [late_refit, late_rebuild] = refit_and_rebuild_cost(sphere + "&t=0", sphere + "&t=0.5");
    EXPECT_GT(late_refit, 1.2 * late_rebuild);
    EXPECT_GT(late_refit / late_rebuild, early_refit / early_rebuild);
}

// A rigid motion: each moved teapot's subtree keeps its shape, only the few nodes
// above it stretch, so the refitted tree stays close to a rebuild.
TEST(BvhRefit, UnderARigidMotionTheRefitTreeStaysGood) {
    for (const char* later : {"builtin:moving?t=0.125&n=12", "builtin:moving?t=0.5&n=12"}) {
        const auto [refit, rebuild] = refit_and_rebuild_cost("builtin:moving?t=0&n=12", later);
        EXPECT_LT(refit, 1.15 * rebuild) << later;
    }
}

TEST(BvhRefit, OneAndTwoThreadsGiveTheSameTree) {
    const Mesh start = scene("builtin:wave?mesh=builtin:teapot?n=24&t=0");
    const Mesh later = scene("builtin:wave?mesh=builtin:teapot?n=24&t=0.6&height=0.2");
    auto refit_on = [&](int threads) {
        tbb::global_control limit(tbb::global_control::max_allowed_parallelism, size_t(threads));
        Bvh bvh = *build_bvh(start, {});
        EXPECT_FALSE(refit_bvh(bvh, later).has_value());
        gather_refit_stats(bvh);
        return bvh;
    };
    const Bvh one = refit_on(1), two = refit_on(2);
    ASSERT_EQ(one.nodes.size(), two.nodes.size());
    for (size_t n = 0; n < one.nodes.size(); ++n) ASSERT_TRUE(same_box(one.nodes[n].bounds, two.nodes[n].bounds));
    EXPECT_EQ(one.build_stats.sah_cost, two.build_stats.sah_cost);
}

TEST(BvhRefit, EveryBoxIsItsContentsBox) {
    const Mesh start = scene("builtin:wave?mesh=builtin:teapot?n=12&t=0&height=0.3");
    Bvh bvh = *build_bvh(start, {});
    const Mesh later = scene("builtin:wave?mesh=builtin:teapot?n=12&t=0.55&height=0.3");
    ASSERT_FALSE(refit_bvh(bvh, later).has_value());
    expect_tight_boxes(bvh, later);
}

// Triangles that lose their area (all three corners on one line) and get it back:
// no ray hits a zero-area triangle, and the boxes still hold what the leaves test.
TEST(BvhRefit, TrianglesThatCollapseAndReopen) {
    const Mesh open = scene("builtin:soup?n=3000&seed=5");
    Mesh flat = open;
    for (Vec3& p : flat.positions) p.y = 0.0f;  // every triangle's corners in one plane...
    for (size_t i = 0; i < flat.positions.size(); i += 3) flat.positions[i].z = flat.positions[i + 1].z;  // ...some on a line
    flat.name = "the soup flattened";
    check_refit(open, flat, 5'000, 36);
    check_refit(flat, open, 5'000, 37);
    Bvh bvh = *build_bvh(open, {});
    ASSERT_FALSE(refit_bvh(bvh, flat).has_value());
    expect_tight_boxes(bvh, flat);
}

TEST(BvhRefit, AnEmptySceneRefitsToNothing) {
    const Mesh empty = scene("builtin:empty");
    Bvh bvh = *build_bvh(empty, {});
    ASSERT_FALSE(refit_bvh(bvh, empty).has_value());
    gather_refit_stats(bvh);
    EXPECT_TRUE(bvh.nodes.empty());
    NoObserver none;
    EXPECT_FALSE(bvh.intersect_closest(Ray{{0, 0, -5}, {0, 0, 1}}, none).found());
}

TEST(BvhRefit, AnotherTriangleCountIsAnError) {
    Bvh bvh = *build_bvh(scene("builtin:teapot?n=4"), {});
    const auto error = refit_bvh(bvh, scene("builtin:teapot?n=5"));
    ASSERT_TRUE(error.has_value());
    EXPECT_NE(error->message.find("triangles"), std::string::npos) << error->message;
}

TEST(MovingScenes, KeepTheirTrianglesAndMoveTheirVertices) {
    for (const char* name : {"moving?n=4", "wave?mesh=builtin:sphere"}) {
        SCOPED_TRACE(name);
        const Mesh a = scene(std::string("builtin:") + name + "&t=0");
        const Mesh b = scene(std::string("builtin:") + name + "&t=0.25");
        const Mesh a_again = scene(std::string("builtin:") + name + "&t=0");
        ASSERT_EQ(a.indices, b.indices);
        ASSERT_EQ(a.positions.size(), b.positions.size());
        EXPECT_NE(a.positions, b.positions);
        EXPECT_EQ(a.positions, a_again.positions);  // a time is one scene, every time
        // A whole period later the scene is the same up to the rounding of the angle.
        const Mesh one_turn = scene(std::string("builtin:") + name + "&t=1");
        for (size_t i = 0; i < a.positions.size(); ++i) {
            EXPECT_NEAR(a.positions[i].x, one_turn.positions[i].x, 1e-5);
            EXPECT_NEAR(a.positions[i].y, one_turn.positions[i].y, 1e-5);
            EXPECT_NEAR(a.positions[i].z, one_turn.positions[i].z, 1e-5);
        }
    }
}

}  // namespace
