// Two BVHs over the same triangles (the lecture's "which is better?"): the trees'
// pictures against the trees, the answers against brute force, and the lesson the
// built-in 22 triangles are made for.
#include <gtest/gtest.h>

#include <set>

#include "core/accel/brute_force.h"
#include "core/geometry/scene.h"
#include "core/measure/comparison.h"
#include "core/measure/two_bvhs.h"

using namespace accelviz;

namespace {

const Mesh& twenty_two() {
    static const Mesh mesh = *load_scene("builtin:twenty-two");
    return mesh;
}

/// Looking straight at the 22 triangles' plane, as the lecture's preset does.
Camera facing_camera(int width = 160, int height = 120) {
    return Camera(CameraParams{{0, 0.2, 9}, {0, 0.2, 0}, {0, 1, 0}, 45}, width, height);
}

BvhConfig leaf_of_five() {
    BvhConfig config;
    config.max_leaf_size = 5;
    return config;
}

constexpr std::array<BvhBuilder, 2> kMedianAndSah{BvhBuilder::Median, BvhBuilder::SahBinned};

}  // namespace

TEST(TwoBvhs, TheSahTreeIsCheaperOnTheLecturesTwentyTwoTriangles) {
    auto measured = measure_two_bvhs(twenty_two(), facing_camera(), leaf_of_five(), kMedianAndSah);
    ASSERT_TRUE(measured) << measured.error();
    const BvhTreeSummary& median = measured->trees[0];
    const BvhTreeSummary& sah = measured->trees[1];
    EXPECT_EQ(median.builder, BvhBuilder::Median);
    EXPECT_EQ(sah.builder, BvhBuilder::SahBinned);
    // What the scene is made to show: the median split cuts a cluster in two.
    EXPECT_LT(sah.stats.sah_cost, 0.9 * median.stats.sah_cost);
    EXPECT_LT(sah.nodes_per_ray, median.nodes_per_ray);
    EXPECT_LE(sah.triangle_tests_per_ray, median.triangle_tests_per_ray);
    EXPECT_GT(measured->rays_that_hit, 0u);
    EXPECT_LT(measured->rays_that_hit, measured->rays_meeting_root);  // rays pass between the triangles
    EXPECT_LE(measured->rays_meeting_root, measured->rays);
}

TEST(TwoBvhs, BothTreesAnswerAsBruteForceOverTheSampledRays) {
    for (const char* scene : {"builtin:twenty-two", "builtin:teapot?n=3", "builtin:same-centroid?n=40"}) {
        SCOPED_TRACE(scene);
        const Mesh mesh = *load_scene(scene);
        const Camera camera(default_camera(mesh.bounds()), 96, 64);
        TwoBvhsOptions options;
        options.sample_rays = 500;
        auto measured = measure_two_bvhs(mesh, camera, BvhConfig{}, {BvhBuilder::Midpoint, BvhBuilder::SahSweep},
                                         options);
        ASSERT_TRUE(measured) << measured.error();
        EXPECT_EQ(measured->rays, 500u);
        EXPECT_EQ(measured->disagreements, 0u);
        const BruteForce naive(mesh);
        NoObserver no_observer;
        uint64_t hits = 0;
        for (const Ray& ray : comparison_rays(camera, options.sample_rays, options.seed))
            hits += naive.intersect_closest(ray, no_observer).found() ? 1 : 0;
        EXPECT_EQ(measured->rays_that_hit, hits);
    }
}

TEST(TwoBvhs, BoxesAndLeavesDescribeTheTree) {
    auto measured = measure_two_bvhs(twenty_two(), facing_camera(), leaf_of_five(), kMedianAndSah);
    ASSERT_TRUE(measured) << measured.error();
    for (const BvhTreeSummary& tree : measured->trees) {
        SCOPED_TRACE(std::string(to_string(tree.builder)));
        ASSERT_EQ(tree.boxes.size(), tree.stats.nodes);
        uint32_t leaves = 0, deepest = 0;
        for (const auto& box : tree.boxes) {
            leaves += box.leaf ? 1 : 0;
            deepest = std::max(deepest, box.depth);
        }
        EXPECT_EQ(leaves, tree.stats.leaves);
        EXPECT_EQ(deepest, tree.stats.max_depth);
        EXPECT_EQ(tree.boxes[0].depth, 0u);
        EXPECT_FALSE(tree.boxes[0].leaf);  // 22 triangles, leaves of at most 5
        // Each triangle's leaf number names a leaf whose box holds it; every leaf has one.
        std::vector<const BvhTreeSummary::Box*> leaf_boxes;
        for (const auto& box : tree.boxes)
            if (box.leaf) leaf_boxes.push_back(&box);
        ASSERT_EQ(tree.leaf_of_triangle.size(), 22u);
        std::set<uint32_t> used;
        for (uint32_t t = 0; t < 22; ++t) {
            const uint32_t leaf = tree.leaf_of_triangle[t];
            ASSERT_LT(leaf, leaf_boxes.size());
            used.insert(leaf);
            EXPECT_TRUE(leaf_boxes[leaf]->bounds.contains(twenty_two().triangle_bounds(t))) << "triangle " << t;
        }
        EXPECT_EQ(used.size(), leaf_boxes.size());
    }
}

TEST(TwoBvhs, CountsAreThePerRayAveragesOfTheTraversalsOwnCounters) {
    TwoBvhsOptions options;
    options.sample_rays = 64;
    // A wide view: some rays miss the root's box and are left out of the averages (8 x 8
    // pixels 2.25 apart at z = 0, none near the box's edges).
    const Camera camera(CameraParams{{0, 0.2, 9}, {0, 0.2, 0}, {0, 1, 0}, 90}, 8, 8);
    auto measured = measure_two_bvhs(twenty_two(), camera, leaf_of_five(), kMedianAndSah, options);
    ASSERT_TRUE(measured) << measured.error();
    const std::vector<Ray> rays = comparison_rays(camera, options.sample_rays, options.seed);
    uint64_t meeting = 0;
    for (const Ray& ray : rays)
        if (slab_test(twenty_two().bounds(), RayPrecomp(ray)).hit()) ++meeting;
    EXPECT_EQ(measured->rays_meeting_root, meeting);
    ASSERT_GT(meeting, 0u);
    ASSERT_LT(meeting, rays.size());
    // Each figure is a count over the rays that meet the root's box.
    for (const BvhTreeSummary& tree : measured->trees) {
        for (double per_ray : {tree.nodes_per_ray, tree.box_tests_per_ray, tree.triangle_tests_per_ray}) {
            const double total = per_ray * double(meeting);
            EXPECT_NEAR(total, std::round(total), 1e-9);
        }
        EXPECT_GE(tree.nodes_per_ray, 1.0);  // each of them visits the root at least
    }
}

TEST(TwoBvhs, ACancelledMeasurementSaysSo) {
    WorkProgress progress;
    progress.cancel();
    TwoBvhsOptions options;
    options.progress = &progress;
    auto measured = measure_two_bvhs(twenty_two(), facing_camera(), leaf_of_five(), kMedianAndSah, options);
    ASSERT_FALSE(measured);
    EXPECT_EQ(measured.error(), WorkProgress::cancelled_error().message);
}

TEST(TwoBvhs, AnInvalidConfigIsAnError) {
    BvhConfig config;
    config.max_leaf_size = 0;
    auto measured = measure_two_bvhs(twenty_two(), facing_camera(), config, kMedianAndSah);
    ASSERT_FALSE(measured);
    EXPECT_NE(measured.error().find("leaf"), std::string::npos) << measured.error();
}
