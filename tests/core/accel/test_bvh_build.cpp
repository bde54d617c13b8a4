// The BVH builders' structural promises: every triangle reachable exactly once,
// every box the union of what is below it (so inside its parent), leaves within
// the size limit, no leaf deeper than the traversal stack allows, stats that add
// up and explain the lecture's tricky cases, a build recorder that replays the
// decisions, and builds that never compute on a subnormal number (the slow path).
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include <tbb/global_control.h>

#include "core/accel/brute_force.h"
#include "core/accel/bvh_build.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "test_support.h"

using namespace accelviz;

namespace {

const BvhBuilder kBuilders[] = {BvhBuilder::Midpoint, BvhBuilder::Median, BvhBuilder::SahSweep, BvhBuilder::SahBinned};

Mesh scene(const std::string& source) {
    auto mesh = load_scene(source);
    EXPECT_TRUE(mesh.ok()) << source << ": " << mesh.error();
    return mesh.ok() ? *mesh : Mesh{};
}

bool same_bits(const Triangle& a, const Triangle& b) { return std::memcmp(&a, &b, sizeof(Triangle)) == 0; }

/// Checks every structural invariant of `bvh` over `mesh`.
void check_invariants(const Mesh& mesh, const Bvh& bvh) {
    const size_t n = mesh.triangle_count();
    const BvhBuildStats& stats = bvh.build_stats;
    ASSERT_EQ(bvh.prim_ids.size(), n);
    ASSERT_EQ(bvh.triangles.size(), n);
    EXPECT_EQ(stats.triangles, n);
    if (n == 0) {
        EXPECT_TRUE(bvh.nodes.empty());
        EXPECT_EQ(stats.nodes, 0u);
        return;
    }
    EXPECT_LE(bvh.nodes.size(), 2 * n - 1);

    // The leaf-ordered copy is exactly what make_triangles builds, bit for bit.
    for (size_t k = 0; k < n; ++k) ASSERT_TRUE(same_bits(bvh.triangles[k], mesh.triangle(bvh.prim_ids[k]))) << k;

    // Walk the tree (explicit stack): every node reached once, leaf ranges tile [0, n).
    std::vector<int> node_seen(bvh.nodes.size(), 0), position_seen(n, 0), id_seen(n, 0);
    struct Item { uint32_t node, depth; };
    std::vector<Item> stack = {{0, 0}};
    uint32_t leaves = 0, max_depth = 0, over_limit = 0;
    std::vector<uint32_t> histogram;
    while (!stack.empty()) {
        const Item item = stack.back();
        stack.pop_back();
        ASSERT_LT(item.node, bvh.nodes.size());
        ASSERT_EQ(node_seen[item.node]++, 0) << "node " << item.node << " reached twice";
        const BvhNode& node = bvh.nodes[item.node];
        ASSERT_LE(item.depth, kBvhMaxDepth);
        max_depth = std::max(max_depth, item.depth);
        if (node.is_leaf()) {
            ++leaves;
            if (node.count > uint32_t(bvh.build_config.max_leaf_size)) ++over_limit;
            if (histogram.size() <= node.count) histogram.resize(node.count + 1, 0);
            ++histogram[node.count];
            ASSERT_LE(size_t(node.first) + node.count, n);
            Aabb box;  // a leaf's box is exactly the union of its triangles' boxes
            for (uint32_t k = node.first; k < node.first + node.count; ++k) {
                ++position_seen[k];
                ++id_seen[bvh.prim_ids[k]];
                box.grow(mesh.triangle_bounds(bvh.prim_ids[k]));
            }
            EXPECT_EQ(box, node.bounds) << "leaf " << item.node;
        } else {
            ASSERT_LT(size_t(node.first) + 1, bvh.nodes.size());
            const Aabb& left = bvh.nodes[node.first].bounds;
            const Aabb& right = bvh.nodes[node.first + 1].bounds;
            EXPECT_TRUE(node.bounds.contains(left) && node.bounds.contains(right)) << "node " << item.node;
            EXPECT_EQ(merge(left, right), node.bounds) << "node " << item.node;  // tight
            stack.push_back({node.first, item.depth + 1});
            stack.push_back({node.first + 1, item.depth + 1});
        }
    }
    for (size_t i = 0; i < bvh.nodes.size(); ++i) EXPECT_EQ(node_seen[i], 1) << "node " << i << " unreachable";
    for (size_t k = 0; k < n; ++k) {
        EXPECT_EQ(position_seen[k], 1) << "leaf position " << k;
        EXPECT_EQ(id_seen[k], 1) << "triangle " << k << " must be in exactly one leaf";
    }
    // Stats agree with the tree, and leaves over the limit are explained.
    EXPECT_EQ(stats.nodes, bvh.nodes.size());
    EXPECT_EQ(stats.leaves, leaves);
    EXPECT_EQ(stats.max_depth, max_depth);
    EXPECT_EQ(stats.leaf_size_histogram, histogram);
    EXPECT_EQ(stats.leaves_over_limit, over_limit);
    if (over_limit > 0) {
        EXPECT_FALSE(stats.notes.empty());
    }
    uint32_t decisions = 0;
    for (uint32_t d : stats.decisions) decisions += d;
    EXPECT_EQ(decisions, stats.nodes) << "one decision per node";
    EXPECT_EQ(stats.memory_bytes, bvh.nodes.size() * 32 + n * 4 + n * sizeof(Triangle));
    EXPECT_GT(stats.sah_cost, 0.0);
}

bool notes_mention(const BvhBuildStats& stats, const std::string& text) {
    for (const std::string& note : stats.notes)
        if (note.find(text) != std::string::npos) return true;
    return false;
}

/// Two trees with the same nodes (bit for bit) and the same triangle order.
void expect_same_tree(const Bvh& a, const Bvh& b) {
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (size_t i = 0; i < a.nodes.size(); ++i)
        ASSERT_EQ(std::memcmp(&a.nodes[i], &b.nodes[i], sizeof(BvhNode)), 0) << "node " << i;
    EXPECT_TRUE(std::equal(a.prim_ids.begin(), a.prim_ids.end(), b.prim_ids.begin(), b.prim_ids.end()));
    EXPECT_EQ(a.build_stats.sah_cost, b.build_stats.sah_cost);
    EXPECT_EQ(a.build_stats.decisions, b.build_stats.decisions);
}

}  // namespace

TEST(BvhBuild, InvariantsHoldForEveryBuilderOnEveryScene) {
    const std::vector<std::string> sources = {
        "builtin:cube",          "builtin:cornell",  "builtin:teapot?n=4",  "builtin:stadium?n=4",
        "builtin:same-centroid", "builtin:same-box", "builtin:soup?n=3000", "builtin:single",
        "builtin:empty",         "builtin:sphere?subdiv=2"};
    for (const std::string& source : sources) {
        const Mesh mesh = scene(source);
        for (BvhBuilder builder : kBuilders)
            for (int leaf : {1, 4, 7}) {
                SCOPED_TRACE(source + " " + std::string(to_string(builder)) + " leaf " + std::to_string(leaf));
                check_invariants(mesh, *build_bvh(mesh, {.builder = builder, .max_leaf_size = leaf}));
            }
    }
}

TEST(BvhBuild, InvariantsHoldOnTheBunny) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = scene(test::shared_asset("bunny.obj"));
    for (BvhBuilder builder : kBuilders) {
        SCOPED_TRACE(to_string(builder));
        check_invariants(mesh, *build_bvh(mesh, {.builder = builder}));
    }
}

TEST(BvhBuild, EmptySceneHasNoNodesAndSaysSo) {
    const Bvh bvh = *build_bvh(Mesh{}, {});
    EXPECT_TRUE(bvh.nodes.empty());
    EXPECT_TRUE(notes_mention(bvh.build_stats, "empty scene"));
    NoObserver none;
    EXPECT_FALSE(bvh.intersect_closest(Ray{{0, 0, -1}, {0, 0, 1}}, none).found());
    EXPECT_FALSE(bvh.intersect_any(Ray{{0, 0, -1}, {0, 0, 1}}));
}

TEST(BvhBuild, OneTriangleIsOneLeaf) {
    const Mesh mesh = scene("builtin:single");
    for (BvhBuilder builder : kBuilders) {
        const Bvh bvh = *build_bvh(mesh, {.builder = builder});
        ASSERT_EQ(bvh.nodes.size(), 1u);
        EXPECT_TRUE(bvh.nodes[0].is_leaf());
        EXPECT_EQ(bvh.nodes[0].count, 1u);
        EXPECT_EQ(bvh.build_stats.max_depth, 0u);
    }
}

// Lecture, 棘手的情况: all centroids equal. No plane separates them, so every
// builder splits by index, and the stats say so.
TEST(BvhBuild, SameCentroidIsSplitByIndexAndExplained) {
    const Mesh mesh = scene("builtin:same-centroid");
    for (BvhBuilder builder : kBuilders) {
        SCOPED_TRACE(to_string(builder));
        const Bvh bvh = *build_bvh(mesh, {.builder = builder});
        const BvhBuildStats& s = bvh.build_stats;
        EXPECT_GT(s.count(BuildDecision::SplitInHalfCentroidsEqual), 0u);
        EXPECT_EQ(s.count(BuildDecision::Split), 0u);
        EXPECT_TRUE(notes_mention(s, "centroids are equal")) << nlohmann::json(s.notes).dump();
        EXPECT_EQ(s.leaves_over_limit, 0u);
        // Halving 1000 triangles down to leaves of at most 4: a balanced tree.
        EXPECT_LE(s.max_depth, 8u);
    }
}

// Lecture, 棘手的情况: all boxes equal. Any split leaves both children as big as
// the parent, so SAH never finds one cheaper than a leaf; leaves must still fit.
TEST(BvhBuild, SameBoxSplitsOnlyBecauseLeavesMustFitAndSaysSo) {
    const Mesh mesh = scene("builtin:same-box");
    for (BvhBuilder builder : {BvhBuilder::SahSweep, BvhBuilder::SahBinned}) {
        SCOPED_TRACE(to_string(builder));
        const Bvh bvh = *build_bvh(mesh, {.builder = builder});
        const BvhBuildStats& s = bvh.build_stats;
        EXPECT_EQ(s.count(BuildDecision::Split), 0u);
        EXPECT_GT(s.count(BuildDecision::SplitForcedBySize), 0u);
        EXPECT_TRUE(notes_mention(s, "a leaf may hold at most 4")) << nlohmann::json(s.notes).dump();
        for (const BvhNode& node : bvh.nodes) EXPECT_EQ(node.bounds, bvh.nodes[0].bounds);
        // Every plane costs the same, so the most even one is taken (is_better_split):
        // about log2(1000 / 4) levels, not a chain that peels a few triangles per level.
        EXPECT_LE(s.max_depth, 9u);
    }
}

// Centroids spread over the whole float range (2^-100 .. 2^100) make the midpoint
// heuristic peel off one triangle per level: without the depth budget the tree would be
// ~200 deep and overflow the 64-entry traversal stack.
TEST(BvhBuild, DepthIsBoundedOnPathologicalInput) {
    Mesh mesh;
    for (int e = -100; e <= 100; ++e)
        for (int copy = 0; copy < 3; ++copy) {
            const float x = std::ldexp(1.0f, e);
            mesh.add_triangle({x, float(copy), 0}, {x, float(copy) + 1, 0}, {x, float(copy), 1});
        }
    for (BvhBuilder builder : kBuilders) {
        SCOPED_TRACE(to_string(builder));
        const Bvh bvh = *build_bvh(mesh, {.builder = builder, .max_leaf_size = 1});
        check_invariants(mesh, bvh);
        EXPECT_LE(bvh.build_stats.max_depth, kBvhMaxDepth);
    }
    const Bvh midpoint = *build_bvh(mesh, {.builder = BvhBuilder::Midpoint, .max_leaf_size = 1});
    EXPECT_GT(midpoint.build_stats.count(BuildDecision::SplitInHalfDepthBudget), 0u);
    EXPECT_TRUE(notes_mention(midpoint.build_stats, "deeper than 63 levels"));
    // And it still answers exactly: rays along x through every triangle's plane (ties at t = 1).
    const BruteForce brute(mesh);
    for (const Ray& ray : {Ray{{-1, 0.5f, 0.25f}, {1, 0, 0}}, Ray{{-1, 1.5f, 0.25f}, {1, 0, 0}},
                           Ray{{1e30f, 2.25f, 0.5f}, {-1, 0, 0}}, Ray{{-1, 0.3f, 0.3f}, {1, 1e-3f, 1e-3f}}}) {
        NoObserver none;
        const Hit expected = brute.intersect_closest(ray, none);
        const Hit got = midpoint.intersect_closest(ray, none);
        EXPECT_TRUE(expected.found());
        EXPECT_EQ(got.tri, expected.tri);
        EXPECT_EQ(got.t, expected.t);
    }
}

TEST(BvhBuild, ZeroExtentAxesAreSkipped) {
    // All triangles in the plane z = 0 with centroids on the line y = 0: only x separates them.
    Mesh mesh;
    for (int i = 0; i < 64; ++i) mesh.add_triangle({float(i), -1, 0}, {float(i) + 1, 0, 0}, {float(i), 1, 0});
    for (BvhBuilder builder : kBuilders) {
        SCOPED_TRACE(to_string(builder));
        BuildRecorder recorder;
        const Bvh bvh = *build_bvh(mesh, {.builder = builder}, &recorder);
        check_invariants(mesh, bvh);
        for (const BuildStep& step : recorder.steps) {
            if (step.axis >= 0) {
                EXPECT_EQ(step.axis, 0);
            }
            EXPECT_TRUE(step.candidate_costs[1].empty() && step.candidate_costs[2].empty());
        }
        EXPECT_EQ(bvh.build_stats.count(BuildDecision::SplitInHalfCentroidsEqual), 0u);
    }
}

TEST(BvhBuild, SahStopsWhenNoSplitIsCheaperThanTheLeaf) {
    // A huge C_trav makes every split dearer than a leaf of 4: SAH then splits only
    // nodes that do not fit, and its leaves are as full as allowed.
    const Mesh mesh = scene("builtin:soup?n=2000");
    const Bvh bvh = *build_bvh(mesh, {.builder = BvhBuilder::SahBinned, .cost_trav = 1000.0f});
    EXPECT_EQ(bvh.build_stats.count(BuildDecision::Split), 0u);
    EXPECT_GT(bvh.build_stats.count(BuildDecision::LeafCheaper), 0u);
    // A tiny C_trav with one-triangle leaves allowed: SAH splits almost everything.
    const Bvh deep = *build_bvh(mesh, {.builder = BvhBuilder::SahBinned, .max_leaf_size = 8, .cost_trav = 0.01f});
    EXPECT_GT(deep.build_stats.count(BuildDecision::Split), 500u);
}

TEST(BvhBuild, SahCostOfSahBuildersBeatsTheHeuristicsOnTheBunny) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = scene(test::shared_asset("bunny.obj"));
    auto cost = [&](BvhBuilder b) { return build_bvh(mesh, {.builder = b})->build_stats.sah_cost; };
    const double sweep = cost(BvhBuilder::SahSweep), binned = cost(BvhBuilder::SahBinned);
    EXPECT_LT(sweep, cost(BvhBuilder::Median));
    EXPECT_LT(binned, cost(BvhBuilder::Midpoint));
}

TEST(BvhBuild, RecorderReplaysEveryDecision) {
    const Mesh mesh = scene("builtin:teapot?n=2");
    for (BvhBuilder builder : kBuilders) {
        SCOPED_TRACE(to_string(builder));
        BuildRecorder recorder;
        const BvhConfig config{.builder = builder, .bins = 8};
        const Bvh bvh = *build_bvh(mesh, config, &recorder);
        expect_same_tree(*build_bvh(mesh, config), bvh);  // recording must not change the tree
        ASSERT_EQ(recorder.steps.size(), bvh.nodes.size());
        EXPECT_EQ(recorder.steps[0].node, 0u);
        std::vector<const BuildStep*> step_of(bvh.nodes.size(), nullptr);
        for (const BuildStep& step : recorder.steps) step_of[step.node] = &step;
        std::array<uint32_t, kBuildDecisionCount> counts{};
        for (const BuildStep& step : recorder.steps) {
            ++counts[size_t(step.decision)];
            const BvhNode& node = bvh.nodes[step.node];
            EXPECT_EQ(step.bounds, node.bounds);
            if (node.is_leaf()) {
                EXPECT_EQ(step.first, node.first);
                EXPECT_EQ(step.count, node.count);
            } else {
                // The children's ranges are the two parts of the parent's.
                const BuildStep* left = step_of[node.first];
                const BuildStep* right = step_of[node.first + 1];
                ASSERT_TRUE(left && right);
                EXPECT_EQ(left->first, step.first);
                EXPECT_EQ(left->count, step.left_count);
                EXPECT_EQ(right->first, step.first + step.left_count);
                EXPECT_EQ(right->count, step.count - step.left_count);
                EXPECT_EQ(left->depth, step.depth + 1);
                EXPECT_TRUE(std::isfinite(step.split_cost));
            }
            EXPECT_FLOAT_EQ(step.leaf_cost, float(step.count) * config.cost_isect);
            if (builder == BvhBuilder::SahBinned && step.count > 1 && !(step.centroid_bounds.extent().x == 0)) {
                EXPECT_EQ(step.candidate_costs[0].size(), 7u);
            }
            if (step.decision == BuildDecision::Split &&
                (builder == BvhBuilder::SahBinned || builder == BvhBuilder::SahSweep)) {
                // The chosen split is the cheapest candidate, and cheaper than the leaf.
                float cheapest = kInfinity;
                for (const auto& costs : step.candidate_costs)
                    for (float c : costs) cheapest = std::min(cheapest, c);
                EXPECT_LT(cheapest, step.leaf_cost);
                EXPECT_FLOAT_EQ(step.split_cost, cheapest);
            }
        }
        EXPECT_EQ(counts, bvh.build_stats.decisions);
    }
}

TEST(BvhBuild, BinnedShortcutsBuildTheSameTreeAsTheFullBinning) {
    // Recording every candidate makes sah-binned bin every node in full (all B bins per
    // axis); without it, nodes of few triangles take find_split_among_few and big ones
    // two sets of bins. Both must make the same decisions, so the same tree.
    std::vector<std::string> sources = {"builtin:teapot?n=4", "builtin:stadium", "builtin:soup?n=3000",
                                        "builtin:same-centroid", "builtin:same-box", "builtin:cornell"};
    if (test::shared_asset_exists("bunny.obj")) sources.push_back(test::shared_asset("bunny.obj"));
    for (const std::string& source : sources) {
        const Mesh mesh = scene(source);
        for (int bins : {2, 5, 16, 64}) {
            SCOPED_TRACE(source + ", " + std::to_string(bins) + " bins");
            const BvhConfig config{.builder = BvhBuilder::SahBinned, .bins = bins};
            BuildRecorder recorder;  // record_candidates: every node binned in full
            expect_same_tree(*build_bvh(mesh, config, &recorder), *build_bvh(mesh, config));
        }
    }
}

#if defined(__SSE2__)
TEST(BvhBuild, BuildsWithoutComputingOnSubnormalNumbers) {
    // Every builder keeps each triangle's id in the four bytes after its centroid, and
    // read as a float an id from 1 to 2^23 - 1 is a subnormal number; a CPU computes
    // with subnormals on a slow path (binning by those four floats once made the build
    // twice as slow). The SSE status register's sticky "denormal operand" flag
    // (MXCSR.DE, bit 1) tells whether any float operation of this thread saw one; the
    // build runs on the calling thread. These scenes' coordinates are ordinary numbers,
    // so a clean build leaves the flag clear.
    constexpr unsigned kDenormalFlag = 1u << 1, kAllFlags = 0x3f;
    constexpr unsigned kDenormalsAreZero = 1u << 6;  // DAZ would hide subnormals (and the flag)
    ASSERT_EQ(_mm_getcsr() & kDenormalsAreZero, 0u) << "compiled or run with denormals-are-zero: nothing to see";
    std::vector<std::string> sources = {"builtin:soup?n=5000", "builtin:teapot"};
    if (test::shared_asset_exists("bunny.obj")) sources.push_back(test::shared_asset("bunny.obj"));
    for (const std::string& source : sources) {
        const Mesh mesh = scene(source);
        for (BvhBuilder builder : kBuilders) {
            SCOPED_TRACE(source + ", " + std::string(to_string(builder)));
            _mm_setcsr(_mm_getcsr() & ~kAllFlags);
            const Bvh bvh = *build_bvh(mesh, {.builder = builder});
            const unsigned flags = _mm_getcsr();
            EXPECT_EQ(flags & kDenormalFlag, 0u) << "a float operation of the build saw a subnormal operand";
            EXPECT_GT(bvh.nodes.size(), 0u);
        }
    }
}
#endif

TEST(BvhBuild, BuilderRefusesWhatValidateRefuses) {
    const Mesh mesh = scene("builtin:cube");
    for (BvhConfig bad : {BvhConfig{.bins = kBvhMinBins - 1}, BvhConfig{.bins = kBvhMaxBins + 1},
                          BvhConfig{.max_leaf_size = 0}, BvhConfig{.max_leaf_size = kBvhMaxLeafSize + 1},
                          BvhConfig{.cost_isect = 0.0f}}) {
        auto bvh = build_bvh(mesh, bad);
        ASSERT_FALSE(bvh.ok()) << "built with bins " << bad.bins << ", leaf size " << bad.max_leaf_size;
        EXPECT_EQ(bvh.error(), validate(bad)->message);
    }
    EXPECT_TRUE(build_bvh(mesh, {.bins = kBvhMaxBins, .max_leaf_size = kBvhMaxLeafSize}).ok());
}

TEST(BvhBuild, FactoryValidatesTheConfig) {
    const Mesh mesh = scene("builtin:cube");
    AccelConfig config;
    config.type = AccelType::Bvh;
    config.bvh.bins = 1;
    auto bad = build_accelerator(mesh, config);
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().find("--bins"), std::string::npos);
    config.bvh = {};
    config.bvh.max_leaf_size = 0;
    EXPECT_FALSE(build_accelerator(mesh, config).ok());
    config.bvh = {};
    config.bvh.cost_isect = 0;
    EXPECT_FALSE(build_accelerator(mesh, config).ok());
    config.bvh = {};
    config.bvh_traversal = BvhTraversal::Unordered;
    auto good = build_accelerator(mesh, config);
    ASSERT_TRUE(good.ok()) << good.error();
    EXPECT_EQ((*good)->name(), "bvh");
    EXPECT_EQ((*good)->config()["traversal"], "unordered");
    EXPECT_EQ((*good)->config()["builder"], "sah-binned");
    EXPECT_EQ((*good)->stats()["triangles"], 12);
}

TEST(BvhBuild, SubtreesBuiltInParallelMakeTheDepthFirstTree) {
    // Above a few thousand triangles the two children of a node are built in parallel and
    // stitched together after; with a recorder one task builds the whole tree depth first.
    // Both must give the same nodes in the same places, on one thread and on all.
    std::vector<std::string> sources = {"builtin:soup?n=20000&seed=3", "builtin:teapot?n=24"};
    if (test::shared_asset_exists("bunny.obj")) sources.push_back(test::shared_asset("bunny.obj"));
    for (const std::string& source : sources) {
        const Mesh mesh = scene(source);
        ASSERT_GT(mesh.triangle_count(), 10000u) << "too small to be built in parallel";
        for (BvhBuilder builder : kBuilders) {
            SCOPED_TRACE(source + ", " + std::string(to_string(builder)));
            const BvhConfig config{.builder = builder};
            BuildRecorder recorder;
            recorder.record_candidates = false;
            const Bvh depth_first = *build_bvh(mesh, config, &recorder);
            expect_same_tree(depth_first, *build_bvh(mesh, config));
            tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
            expect_same_tree(depth_first, *build_bvh(mesh, config));
        }
    }
}

