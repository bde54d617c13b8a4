// The construction stepper's SAH chart: recomputed from one node's triangles, it
// must give the builder's own numbers (candidate by candidate, and the chosen
// split), follow new parameters, and say why no split helps on the tricky scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <span>

#include "core/accel/bvh_build.h"
#include "core/accel/sah_chart.h"
#include "core/geometry/scene.h"
#include "test_support.h"

using namespace accelviz;

namespace {

Mesh scene(const std::string& source) {
    auto mesh = load_scene(source);
    EXPECT_TRUE(mesh.ok()) << source << ": " << mesh.error();
    return mesh.ok() ? *mesh : Mesh{};
}

std::span<const uint32_t> prims(const Bvh& bvh, const BuildStep& step) {
    return std::span<const uint32_t>(bvh.prim_ids).subspan(step.first, step.count);
}

bool is_leaf(BuildDecision d) {
    return d == BuildDecision::LeafFits || d == BuildDecision::LeafCheaper ||
           d == BuildDecision::LeafNoSeparatingPlane || d == BuildDecision::LeafDepthLimit;
}

/// Recomputes the chart of the first `max_steps` recorded decisions and compares
/// it with what the builder recorded.
void expect_chart_matches_recording(const Mesh& mesh, const BvhConfig& config, size_t max_steps) {
    BuildRecorder recorder;
    const Bvh bvh = *build_bvh(mesh, config, &recorder);
    ASSERT_FALSE(recorder.steps.empty());
    size_t splits_checked = 0;
    for (size_t s = 0; s < std::min(max_steps, recorder.steps.size()); ++s) {
        const BuildStep& step = recorder.steps[s];
        SCOPED_TRACE("step " + std::to_string(s) + " node " + std::to_string(step.node));
        const SahChart chart = compute_sah_chart(mesh, prims(bvh, step), config);
        EXPECT_EQ(chart.count, step.count);
        EXPECT_EQ(chart.bounds, step.bounds);
        EXPECT_EQ(chart.centroid_bounds, step.centroid_bounds);
        EXPECT_EQ(chart.leaf_cost, step.leaf_cost);
        if (step.count > 1 && !is_leaf(step.decision)) {
            // The builder searched: every candidate, bit for bit.
            for (int axis = 0; axis < 3; ++axis) {
                EXPECT_EQ(chart.axes[axis].positions, step.candidate_positions[axis]) << "axis " << axis;
                EXPECT_EQ(chart.axes[axis].costs, step.candidate_costs[axis]) << "axis " << axis;
            }
        }
        if (step.decision == BuildDecision::Split) {
            // The recorded chosen cost is the recomputed minimum for the same parameters.
            EXPECT_EQ(chart.best_cost, step.split_cost);
            EXPECT_EQ(chart.best_axis, step.axis);
            EXPECT_EQ(chart.best_position, step.split_position);
            EXPECT_EQ(chart.best_left_count, step.left_count);
            EXPECT_EQ(chart.verdict, ChartVerdict::Split);
            const BvhNode& node = bvh.nodes[step.node];
            EXPECT_EQ(chart.best_children[0], bvh.nodes[node.first].bounds);
            EXPECT_EQ(chart.best_children[1], bvh.nodes[node.first + 1].bounds);
            ++splits_checked;
        }
        if (step.decision == BuildDecision::LeafCheaper) {
            EXPECT_EQ(chart.verdict, ChartVerdict::LeafCheaper);
            EXPECT_GE(chart.best_cost, chart.leaf_cost);
        }
        if (step.decision == BuildDecision::SplitForcedBySize) {
            EXPECT_EQ(chart.verdict, ChartVerdict::SplitForcedBySize);
            EXPECT_EQ(chart.best_cost, step.split_cost);
            EXPECT_EQ(chart.best_axis, step.axis);
            EXPECT_EQ(chart.best_position, step.split_position);
            EXPECT_EQ(chart.best_left_count, step.left_count);
        }
    }
    EXPECT_GT(splits_checked, 0u);
}

}  // namespace

TEST(SahChart, BinnedBunnyMatchesTheBuilderCandidateByCandidate) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = scene(test::shared_asset("bunny.obj"));
    expect_chart_matches_recording(mesh, {.builder = BvhBuilder::SahBinned}, 60);
    expect_chart_matches_recording(mesh, {.builder = BvhBuilder::SahBinned, .bins = 5, .cost_trav = 3.0f}, 30);
}

TEST(SahChart, SweepMatchesTheBuilderCandidateByCandidate) {
    const Mesh mesh = scene("builtin:teapot?n=3");
    expect_chart_matches_recording(mesh, {.builder = BvhBuilder::SahSweep}, 200);
    const Mesh soup = scene("builtin:soup?n=500");
    expect_chart_matches_recording(soup, {.builder = BvhBuilder::SahSweep, .cost_trav = 0.2f, .cost_isect = 2.0f}, 200);
}

TEST(SahChart, WholeTreeAgreesWithEveryRecordedDecision) {
    // Every node of a small scene: the chart's verdict is the builder's decision.
    const Mesh mesh = scene("builtin:soup?n=300");
    const BvhConfig config{.builder = BvhBuilder::SahBinned, .bins = 8, .cost_trav = 2.0f};
    BuildRecorder recorder;
    const Bvh bvh = *build_bvh(mesh, config, &recorder);
    for (const BuildStep& step : recorder.steps) {
        const SahChart chart = compute_sah_chart(mesh, prims(bvh, step), config);
        EXPECT_FALSE(chart.best_tied);  // random triangles: no two different divisions cost exactly the same
        switch (step.decision) {
            case BuildDecision::LeafFits: EXPECT_EQ(chart.verdict, ChartVerdict::LeafOneTriangle); break;
            case BuildDecision::LeafCheaper: EXPECT_EQ(chart.verdict, ChartVerdict::LeafCheaper); break;
            case BuildDecision::Split: EXPECT_EQ(chart.verdict, ChartVerdict::Split); break;
            case BuildDecision::SplitForcedBySize: EXPECT_EQ(chart.verdict, ChartVerdict::SplitForcedBySize); break;
            default: ADD_FAILURE() << "unexpected decision " << to_string(step.decision);
        }
    }
}

TEST(SahChart, RecorderWithoutCandidatesRecordsTheSameDecisions) {
    const Mesh mesh = scene("builtin:teapot?n=2");
    const BvhConfig config{.builder = BvhBuilder::SahBinned};
    BuildRecorder full, light;
    light.record_candidates = false;
    (void)build_bvh(mesh, config, &full);
    (void)build_bvh(mesh, config, &light);
    ASSERT_EQ(full.steps.size(), light.steps.size());
    size_t with_candidates = 0;
    for (size_t s = 0; s < full.steps.size(); ++s) {
        const BuildStep &a = full.steps[s], &b = light.steps[s];
        EXPECT_EQ(a.node, b.node);
        EXPECT_EQ(a.decision, b.decision);
        EXPECT_EQ(a.split_cost, b.split_cost);
        EXPECT_EQ(a.split_position, b.split_position);
        for (int axis = 0; axis < 3; ++axis) {
            EXPECT_TRUE(b.candidate_costs[axis].empty());
            with_candidates += a.candidate_costs[axis].empty() ? 0 : 1;
        }
    }
    EXPECT_GT(with_candidates, 0u);
}

TEST(SahChart, NewParametersRecomputeOneNodeWithoutRebuilding) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = scene(test::shared_asset("bunny.obj"));
    BuildRecorder recorder;
    const BvhConfig config{.builder = BvhBuilder::SahBinned};
    const Bvh bvh = *build_bvh(mesh, config, &recorder);
    const BuildStep& root = recorder.steps[0];
    // B = 4: three planes per axis.
    BvhConfig four = config;
    four.bins = 4;
    const SahChart coarse = compute_sah_chart(mesh, prims(bvh, root), four);
    for (const SahChartAxis& axis : coarse.axes) EXPECT_EQ(axis.positions.size(), 3u);
    // The recomputed chart is what a whole rebuild with B = 4 records at its root.
    BuildRecorder rebuilt;
    (void)build_bvh(mesh, four, &rebuilt);
    EXPECT_EQ(coarse.best_cost, rebuilt.steps[0].split_cost);
    EXPECT_EQ(coarse.best_position, rebuilt.steps[0].split_position);
    // A huge C_trav makes every split dearer than the leaf; the verdict says so.
    BvhConfig dear = config;
    dear.cost_trav = 1e6f;
    const SahChart chart = compute_sah_chart(mesh, prims(bvh, root), dear);
    EXPECT_GT(chart.best_cost, chart.leaf_cost);
    EXPECT_EQ(chart.verdict, ChartVerdict::SplitForcedBySize);
    EXPECT_NE(chart.verdict_text.find("No split helps"), std::string::npos) << chart.verdict_text;
    // C_isect scales the leaf line and the candidates' variable part.
    BvhConfig isect = config;
    isect.cost_isect = 2.0f;
    EXPECT_EQ(compute_sah_chart(mesh, prims(bvh, root), isect).leaf_cost, 2.0f * float(root.count));
}

TEST(SahChart, HeuristicCutsAreWhereMedianAndMidpointBuildersCut) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = scene(test::shared_asset("bunny.obj"));
    for (BvhBuilder builder : {BvhBuilder::Median, BvhBuilder::Midpoint}) {
        SCOPED_TRACE(std::string(to_string(builder)));
        BuildRecorder recorder;
        const BvhConfig config{.builder = builder};
        const Bvh bvh = *build_bvh(mesh, config, &recorder);
        for (size_t s = 0; s < 20; ++s) {
            const BuildStep& step = recorder.steps[s];
            if (step.decision != BuildDecision::Split && step.decision != BuildDecision::SplitMedianFallback) continue;
            const SahChart chart = compute_sah_chart(mesh, prims(bvh, step), config);
            const HeuristicCut& cut = builder == BvhBuilder::Median ? chart.median : chart.midpoint;
            ASSERT_TRUE(cut.valid);
            EXPECT_EQ(cut.axis, step.axis);
            EXPECT_EQ(cut.position, step.split_position);
            EXPECT_EQ(cut.left_count, step.left_count);
            EXPECT_EQ(cut.cost, step.split_cost);
            EXPECT_EQ(chart.verdict, ChartVerdict::Split);
        }
    }
    // The SAH's cheapest plane is never dearer than either heuristic's cut (binned
    // planes include no exact median, but the sweep's include every centroid).
    BuildRecorder recorder;
    const BvhConfig sweep{.builder = BvhBuilder::SahSweep};
    const Bvh bvh = *build_bvh(mesh, sweep, &recorder);
    const SahChart root = compute_sah_chart(mesh, prims(bvh, recorder.steps[0]), sweep);
    EXPECT_LE(root.best_cost, root.median.cost);
    EXPECT_LE(root.best_cost, root.midpoint.cost);
    EXPECT_LT(root.median.cost, root.leaf_cost);
}

TEST(SahChart, SameCentroidHasNoPlane) {
    const Mesh mesh = scene("builtin:same-centroid?n=200");
    const BvhConfig config{.builder = BvhBuilder::SahBinned};
    BuildRecorder recorder;
    const Bvh bvh = *build_bvh(mesh, config, &recorder);
    const BuildStep& root = recorder.steps[0];
    EXPECT_EQ(root.decision, BuildDecision::SplitInHalfCentroidsEqual);
    const SahChart chart = compute_sah_chart(mesh, prims(bvh, root), config);
    for (const SahChartAxis& axis : chart.axes) {
        EXPECT_FALSE(axis.usable);
        EXPECT_TRUE(axis.positions.empty());
    }
    EXPECT_EQ(chart.best_axis, -1);
    EXPECT_FALSE(chart.median.valid);
    EXPECT_FALSE(chart.midpoint.valid);
    EXPECT_EQ(chart.verdict, ChartVerdict::SplitInHalf);
    EXPECT_NE(chart.verdict_text.find("centroids are equal"), std::string::npos) << chart.verdict_text;
    // A node of the same scene that fits: a leaf, for the same reason.
    for (const BuildStep& step : recorder.steps)
        if (step.decision == BuildDecision::LeafNoSeparatingPlane) {
            EXPECT_EQ(compute_sah_chart(mesh, prims(bvh, step), config).verdict, ChartVerdict::LeafNoPlane);
            return;
        }
    ADD_FAILURE() << "no leaf_no_separating_plane decision recorded";
}

TEST(SahChart, SameBoxEverySplitCostsMoreThanTheLeaf) {
    const Mesh mesh = scene("builtin:same-box?n=200");
    for (BvhBuilder builder : {BvhBuilder::SahBinned, BvhBuilder::SahSweep}) {
        SCOPED_TRACE(std::string(to_string(builder)));
        const BvhConfig config{.builder = builder};
        BuildRecorder recorder;
        const Bvh bvh = *build_bvh(mesh, config, &recorder);
        const SahChart chart = compute_sah_chart(mesh, prims(bvh, recorder.steps[0]), config);
        // Both children keep the parent's box: C_trav + N C_isect > N C_isect, on every plane.
        size_t finite = 0;
        for (const SahChartAxis& axis : chart.axes)
            for (float cost : axis.costs)
                if (cost < kInfinity) {
                    EXPECT_FLOAT_EQ(cost, chart.model.cost_trav + chart.leaf_cost);
                    ++finite;
                }
        EXPECT_GT(finite, 0u);
        EXPECT_EQ(chart.verdict, ChartVerdict::SplitForcedBySize);
        EXPECT_EQ(recorder.steps[0].decision, BuildDecision::SplitForcedBySize);
        EXPECT_NE(chart.verdict_text.find("No split helps"), std::string::npos);
        EXPECT_EQ(chart.median.cost, chart.best_cost);
        // All planes tie, so the builder and the chart both take the most even one
        // (is_better_split), not the first: the tree stays shallow.
        const BuildStep& root = recorder.steps[0];
        EXPECT_EQ(chart.best_axis, root.axis);
        EXPECT_EQ(chart.best_position, root.split_position);
        EXPECT_EQ(chart.best_left_count, root.left_count);
        const uint32_t n = chart.count;
        uint32_t most_even = n;
        for (const SahChartAxis& axis : chart.axes)
            for (size_t i = 0; i < axis.costs.size(); ++i)
                if (axis.costs[i] < kInfinity)
                    most_even = std::min(most_even, std::max(axis.left_counts[i], n - axis.left_counts[i]));
        EXPECT_LT(most_even, n);
        EXPECT_EQ(std::max(root.left_count, n - root.left_count), most_even);
        EXPECT_TRUE(chart.best_tied);
        EXPECT_NE(chart.verdict_text.find("the most even one is taken"), std::string::npos) << chart.verdict_text;
    }
}

TEST(SahChart, SweepSubsamplingKeepsTheMinimum) {
    const Mesh mesh = scene("builtin:soup?n=2000");
    BvhConfig config{.builder = BvhBuilder::SahSweep};
    std::vector<uint32_t> all(mesh.triangle_count());
    for (uint32_t i = 0; i < all.size(); ++i) all[i] = i;
    const SahChart full = compute_sah_chart(mesh, all, config);
    const SahChart shown = compute_sah_chart(mesh, all, config, {.max_points = 100});
    for (int axis = 0; axis < 3; ++axis) {
        EXPECT_EQ(full.axes[axis].positions.size(), 1999u);
        EXPECT_FALSE(full.axes[axis].subsampled);
        EXPECT_TRUE(shown.axes[axis].subsampled);
        EXPECT_LE(shown.axes[axis].positions.size(), 100u);
        EXPECT_EQ(shown.axes[axis].candidates, 1999u);
        EXPECT_EQ(*std::min_element(shown.axes[axis].costs.begin(), shown.axes[axis].costs.end()),
                  *std::min_element(full.axes[axis].costs.begin(), full.axes[axis].costs.end()));
    }
    EXPECT_EQ(shown.best_cost, full.best_cost);
}

TEST(SahChart, EmptyAndSingleNodes) {
    const Mesh mesh = scene("builtin:single");
    const std::vector<uint32_t> none, one = {0};
    EXPECT_EQ(compute_sah_chart(mesh, none, {}).verdict, ChartVerdict::LeafOneTriangle);
    const SahChart chart = compute_sah_chart(mesh, one, {});
    EXPECT_EQ(chart.verdict, ChartVerdict::LeafOneTriangle);
    EXPECT_EQ(chart.best_axis, -1);
    EXPECT_EQ(chart.leaf_cost, 1.0f);
}
