// The overlay's plain data (no GL): which boxes each setting selects.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "app/gui/scene_loader.h"
#include "app/gui/structure_overlay.h"
#include "core/accel/bvh.h"
#include "core/accel/uniform_grid.h"

namespace accelviz {
namespace {

std::shared_ptr<const LoadedScene> teapot_with(const char* type) {
    AccelConfig config;
    config.type = *parse_accel_type(type);
    auto scene = load_and_build("builtin:teapot?n=4", config);
    EXPECT_TRUE(scene) << scene.error();
    return scene ? *scene : nullptr;
}

TEST(StructureOverlay, BvhAllLevelsIsEveryNodeAndLeavesOnlyIsEveryLeaf) {
    auto scene = teapot_with("bvh");
    ASSERT_TRUE(scene);
    ASSERT_NE(structure_if<Bvh>(*scene->accel), nullptr);
    const Bvh& bvh = *structure_if<Bvh>(*scene->accel);
    OverlaySettings all;
    all.max_boxes = 0;
    EXPECT_EQ(make_structure_overlay(*scene->accel, all).boxes.size(), bvh.nodes.size());
    OverlaySettings leaves = all;
    leaves.leaves_only = true;
    size_t leaf_count = 0;
    for (const BvhNode& n : bvh.nodes) leaf_count += n.is_leaf();
    EXPECT_EQ(make_structure_overlay(*scene->accel, leaves).boxes.size(), leaf_count);
}

TEST(StructureOverlay, BoxesComeLevelByLevelSoAMovingCameraDrawsWholeShallowLevels) {
    for (const char* type : {"bvh", "octree", "kd"}) {
        auto scene = teapot_with(type);
        ASSERT_TRUE(scene);
        OverlaySettings all;
        all.max_boxes = 0;
        const StructureOverlay overlay = make_structure_overlay(*scene->accel, all);
        ASSERT_FALSE(overlay.level_ends.empty()) << type;
        EXPECT_EQ(overlay.level_ends.back(), overlay.boxes.size()) << type;
        EXPECT_TRUE(std::is_sorted(overlay.level_ends.begin(), overlay.level_ends.end())) << type;
        // Each level is one colour (the colour map by depth), so a level's boxes share it.
        size_t begin = 0;
        for (size_t end : overlay.level_ends) {
            for (size_t i = begin; i < end; ++i) {
                EXPECT_EQ(overlay.boxes[i].colour.r, overlay.boxes[begin].colour.r) << type << " box " << i;
                EXPECT_EQ(overlay.boxes[i].colour.b, overlay.boxes[begin].colour.b) << type << " box " << i;
            }
            begin = end;
        }
        // The moving prefix: a level's end, the largest within the budget, at least the
        // first level with boxes; the KD tree's planes follow the same levels.
        for (const bool leaves_only : {false, true}) {
            OverlaySettings settings = all;
            settings.leaves_only = leaves_only;
            const StructureOverlay o = make_structure_overlay(*scene->accel, settings);
            const auto first = std::upper_bound(o.level_ends.begin(), o.level_ends.end(), size_t(0));
            ASSERT_NE(first, o.level_ends.end()) << type;
            for (size_t budget : {size_t(0), size_t(1), size_t(40), size_t(300), o.boxes.size()}) {
                const size_t prefix = o.moving_prefix(budget);
                EXPECT_GT(prefix, 0u) << type << " leaves only " << leaves_only << " budget " << budget;
                EXPECT_NE(std::find(o.level_ends.begin(), o.level_ends.end(), prefix), o.level_ends.end());
                EXPECT_TRUE(prefix <= budget || prefix == *first) << type << " budget " << budget;
                const auto next = std::upper_bound(o.level_ends.begin(), o.level_ends.end(), prefix);
                EXPECT_TRUE(next == o.level_ends.end() || *next > budget) << type << " budget " << budget;
                if (std::string(type) == "kd" && !leaves_only) {  // one plane per outline
                    EXPECT_EQ(o.moving_quads(budget), prefix) << "budget " << budget;
                }
            }
        }
    }
    // The grid has no levels: a moving camera draws every cell.
    auto grid = teapot_with("grid");
    ASSERT_TRUE(grid);
    const StructureOverlay cells = make_structure_overlay(*grid->accel, OverlaySettings{});
    EXPECT_TRUE(cells.level_ends.empty());
    EXPECT_EQ(cells.moving_prefix(1), cells.boxes.size());
}

TEST(StructureOverlay, OneLevelShowsItsNodesInOneColour) {
    auto scene = teapot_with("bvh");
    ASSERT_TRUE(scene);
    OverlaySettings level;
    level.level_min = level.level_max = 2;
    const StructureOverlay overlay = make_structure_overlay(*scene->accel, level);
    EXPECT_EQ(overlay.boxes.size(), 4u) << "a binary tree has 4 nodes at depth 2 (the teapot's BVH is that deep)";
    for (const BoxInstance& b : overlay.boxes) EXPECT_EQ(b.colour.r, overlay.boxes[0].colour.r);
}

TEST(StructureOverlay, BudgetCutsDeeperLevelsAndSaysSo) {
    auto scene = teapot_with("bvh");
    ASSERT_TRUE(scene);
    OverlaySettings budget;
    budget.max_boxes = 20;
    const StructureOverlay overlay = make_structure_overlay(*scene->accel, budget);
    EXPECT_LE(overlay.boxes.size(), 20u);
    EXPECT_GE(overlay.boxes.size(), 15u) << "levels 0..3 (15 nodes) fit, level 4 would not";
    EXPECT_NE(overlay.legend.find("hidden"), std::string::npos) << overlay.legend;
}

TEST(StructureOverlay, GridShowsOnlyNonEmptyCellsAndKdShowsPlanes) {
    auto grid = teapot_with("grid");
    ASSERT_TRUE(grid);
    const StructureOverlay cells = make_structure_overlay(*grid->accel, {});
    EXPECT_GT(cells.boxes.size(), 0u);
    EXPECT_TRUE(cells.quads.empty());
    auto kd = teapot_with("kd");
    ASSERT_TRUE(kd);
    OverlaySettings top;
    top.level_max = 0;
    const StructureOverlay planes = make_structure_overlay(*kd->accel, top);
    EXPECT_EQ(planes.quads.size(), 1u) << "the root's split plane";
    auto naive = teapot_with("naive");
    ASSERT_TRUE(naive);
    EXPECT_TRUE(make_structure_overlay(*naive->accel, {}).boxes.empty());
}

TEST(LeafHistogram, BvhLeavesHoldEveryTriangleOnce) {
    auto scene = teapot_with("bvh");
    ASSERT_TRUE(scene);
    const LeafHistogram h = leaf_histogram(*scene->accel);
    EXPECT_EQ(h.what, "BVH leaves");
    ASSERT_NE(structure_if<Bvh>(*scene->accel), nullptr);
    const Bvh& bvh = *structure_if<Bvh>(*scene->accel);
    uint64_t leaves = 0, references = 0;
    for (const BvhNode& n : bvh.nodes) leaves += n.is_leaf();
    for (size_t k = 0; k < h.counts.size(); ++k) references += k * h.counts[k];
    EXPECT_EQ(h.total(), leaves);
    EXPECT_EQ(references, scene->mesh->triangle_count());
    ASSERT_FALSE(h.counts.empty());
    EXPECT_EQ(h.counts[0], 0u);                         // a BVH has no empty leaves
    EXPECT_LE(h.counts.size() - 1, size_t(bvh_config_default().bvh.max_leaf_size));  // SAH stops at the leaf size here
}

TEST(LeafHistogram, GridCountsEveryCellIncludingEmptyOnes) {
    auto scene = teapot_with("grid");
    ASSERT_TRUE(scene);
    const LeafHistogram h = leaf_histogram(*scene->accel);
    EXPECT_EQ(h.what, "grid cells");
    ASSERT_NE(structure_if<UniformGrid>(*scene->accel), nullptr);
    const UniformGrid& grid = *structure_if<UniformGrid>(*scene->accel);
    EXPECT_EQ(h.total(), uint64_t(grid.res[0]) * grid.res[1] * grid.res[2]);
    uint64_t references = 0;
    for (size_t k = 0; k < h.counts.size(); ++k) references += k * h.counts[k];
    EXPECT_EQ(references, grid.cell_start.back());
    EXPECT_GT(h.counts[0], 0u);  // the teapot leaves cells of its box empty
}

TEST(LeafHistogram, NaiveHasNone) {
    auto scene = teapot_with("naive");
    ASSERT_TRUE(scene);
    EXPECT_TRUE(leaf_histogram(*scene->accel).counts.empty());
}

}  // namespace
}  // namespace accelviz
