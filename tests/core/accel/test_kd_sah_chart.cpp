// The KD construction stepper's SAH chart: under the tree's own costs its cheapest
// plane is the plane the build chose, at every interior node; its counts add up; a
// subsampled chart keeps the minimum.
#include <gtest/gtest.h>

#include <algorithm>

#include "core/accel/factory.h"
#include "core/accel/kd_sah_chart.h"
#include "core/geometry/scene.h"

namespace accelviz {
namespace {

const KdTree& kd_of(const Accelerator& accel) { return *structure_if<KdTree>(accel); }

TEST(KdSahChart, TheCheapestPlaneIsTheTreesAtEveryInteriorNode) {
    // The big soup's top nodes sweep their axes and split their references in
    // parallel (kd_tree.cpp): the chart, one sweep after another, must agree there too.
    for (const char* source : {"builtin:teapot", "builtin:soup?n=300", "builtin:soup?n=10000&seed=3"}) {
        auto mesh = load_scene(source, MeshCache::Skip);
        ASSERT_TRUE(mesh.ok()) << source;
        AccelConfig c;
        c.type = AccelType::Kd;
        auto accel = build_accelerator(*mesh, c);
        ASSERT_TRUE(accel.ok()) << accel.error();
        const KdTree& tree = kd_of(**accel);
        // Every node's chart is made again from the root: 150 interior nodes spread over the tree.
        std::vector<uint32_t> interiors;
        for (uint32_t n = 0; n < tree.nodes.size(); ++n)
            if (!tree.nodes[n].is_leaf()) interiors.push_back(n);
        ASSERT_FALSE(interiors.empty()) << source;
        const size_t stride = std::max<size_t>(1, interiors.size() / 150);
        for (size_t k = 0; k < interiors.size(); k += stride) {
            const uint32_t n = interiors[k];
            const KdSahChart chart = kd_sah_chart(*mesh, tree, n, tree.build_config);
            ASSERT_EQ(chart.best_axis, tree.nodes[n].axis()) << source << " node " << n;
            ASSERT_EQ(chart.best_position, tree.nodes[n].split()) << source << " node " << n;
            EXPECT_LT(chart.best_cost, chart.leaf_cost) << "the build split because the plane was cheaper";
            // Each side's count is what the child holds (its subtree's references at its top).
            const KdSahChart lower = kd_sah_chart(*mesh, tree, tree.nodes[n].lower_child(), tree.build_config);
            const KdSahChart upper = kd_sah_chart(*mesh, tree, tree.nodes[n].upper_child(), tree.build_config);
            EXPECT_LE(lower.count, chart.best_below);
            EXPECT_LE(upper.count, chart.best_above);
            EXPECT_EQ(lower.cell.hi[chart.best_axis], chart.best_position);
        }
    }
}

TEST(KdSahChart, TheEmptyBonusAndTheCostsChangeTheCostsNotTheReferences) {
    auto mesh = load_scene("builtin:teapot", MeshCache::Skip);
    ASSERT_TRUE(mesh.ok());
    AccelConfig c;
    c.type = AccelType::Kd;
    auto accel = build_accelerator(*mesh, c);
    ASSERT_TRUE(accel.ok());
    const KdTree& tree = kd_of(**accel);
    KdConfig no_bonus = tree.build_config;
    no_bonus.empty_bonus = 0;
    no_bonus.cost_trav = 0;  // the bonus scales the whole cost, C_trav included
    KdConfig bonus = no_bonus;
    bonus.empty_bonus = 0.5f;
    EXPECT_EQ(kd_sah_chart(*mesh, tree, 0, bonus).count, mesh->triangle_count());
    // A node one of whose planes cuts off empty space (the root's cannot: its cell is the
    // references' own bounds).
    uint32_t node = 1;
    auto has_empty_side = [&](const KdSahChart& chart) {
        for (const KdSahChartAxis& x : chart.axes)
            for (size_t i = 0; i < x.costs.size(); ++i)
                if (x.below[i] == 0 || x.above[i] == 0) return true;
        return false;
    };
    while (node < tree.nodes.size() && !has_empty_side(kd_sah_chart(*mesh, tree, node, bonus))) ++node;
    ASSERT_LT(node, tree.nodes.size());
    const KdSahChart with = kd_sah_chart(*mesh, tree, node, bonus);
    const KdSahChart without = kd_sah_chart(*mesh, tree, node, no_bonus);
    size_t empty_sides = 0;
    for (int a = 0; a < 3; ++a) {
        const KdSahChartAxis& x = with.axes[size_t(a)];
        const KdSahChartAxis& y = without.axes[size_t(a)];
        ASSERT_EQ(x.positions, y.positions);
        for (size_t i = 0; i < x.costs.size(); ++i) {
            EXPECT_EQ(x.below[i], y.below[i]);
            const bool empty = x.below[i] == 0 || x.above[i] == 0;
            empty_sides += empty;
            EXPECT_FLOAT_EQ(x.costs[i], empty ? y.costs[i] * 0.5f : y.costs[i]);
        }
    }
    EXPECT_GT(empty_sides, 0u);
    // Subsampled: fewer points, the same minimum.
    const KdSahChart all = kd_sah_chart(*mesh, tree, 0, tree.build_config);
    const KdSahChart few = kd_sah_chart(*mesh, tree, 0, tree.build_config, 50);
    for (int a = 0; a < 3; ++a) {
        const KdSahChartAxis& x = few.axes[size_t(a)];
        EXPECT_TRUE(x.subsampled);
        EXPECT_LE(x.positions.size(), 50u);
        EXPECT_EQ(x.candidates, all.axes[size_t(a)].positions.size());
        EXPECT_EQ(*std::min_element(x.costs.begin(), x.costs.end()),
                  *std::min_element(all.axes[size_t(a)].costs.begin(), all.axes[size_t(a)].costs.end()));
    }
}

}  // namespace
}  // namespace accelviz
