// The overlay's budget while the camera moves (MovingBoxBudget) follows the frame
// time: slow frames give up a level, fast ones take the next, a machine that got
// faster again gets its level back, and a frame time that grows with the boxes
// settles on one level instead of swinging between two.
#include <gtest/gtest.h>

#include "app/gui/moving_box_budget.h"

namespace accelviz {
namespace {

/// An overlay shaped like a binary tree's levels: 1, 2, 4, ... boxes (`levels` of them).
StructureOverlay binary_levels(int levels) {
    StructureOverlay overlay;
    size_t end = 0;
    for (int level = 0; level < levels; ++level) {
        end += size_t(1) << level;
        overlay.level_ends.push_back(end);
    }
    overlay.boxes.resize(end);
    return overlay;
}

/// One moving frame that took `ms`: drawn, then the next frame starts.
void moving_frame(MovingBoxBudget& budget, const StructureOverlay& overlay, double ms) {
    budget.drew_moving();
    budget.start_frame(ms, overlay);
}

/// A budget whose first frame showed `overlay` (another overlay starts it again).
MovingBoxBudget following(const StructureOverlay& overlay) {
    MovingBoxBudget budget;
    budget.start_frame(0.0, overlay);
    return budget;
}

size_t drawn(const MovingBoxBudget& budget, const StructureOverlay& overlay) {
    return overlay.moving_prefix(budget.boxes());
}

TEST(MovingBoxBudget, TwoSlowFramesInARowGiveUpTheDeepestLevel) {
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    ASSERT_EQ(drawn(budget, overlay), 4095u);  // 12 levels at the start
    moving_frame(budget, overlay, 200.0);     // one slow frame (an upload): nothing yet
    EXPECT_EQ(drawn(budget, overlay), 4095u);
    moving_frame(budget, overlay, 30.0);  // a normal one between: counting starts again
    moving_frame(budget, overlay, 60.0);
    EXPECT_EQ(drawn(budget, overlay), 4095u);
    moving_frame(budget, overlay, 60.0);
    EXPECT_EQ(drawn(budget, overlay), 2047u);
    for (int i = 0; i < 20; ++i) moving_frame(budget, overlay, 500.0);  // however slow: never under the floor
    EXPECT_EQ(drawn(budget, overlay), 1023u);
    EXPECT_GE(budget.boxes(), MovingBoxBudget::kFewestBoxes);
}

TEST(MovingBoxBudget, FramesWithRoomForTheNextLevelTakeIt) {
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    moving_frame(budget, overlay, 10.0);  // 4095 boxes in 10 ms: 8191 would fit even at 2x
    EXPECT_EQ(drawn(budget, overlay), 4095u);
    moving_frame(budget, overlay, 10.0);
    EXPECT_EQ(drawn(budget, overlay), 8191u);
    moving_frame(budget, overlay, 10.0);
    moving_frame(budget, overlay, 10.0);
    EXPECT_EQ(drawn(budget, overlay), 16383u);
    moving_frame(budget, overlay, 25.0);  // twice 25 ms is over the target: stays
    moving_frame(budget, overlay, 25.0);
    EXPECT_EQ(drawn(budget, overlay), 16383u);
    for (int i = 0; i < 20; ++i) moving_frame(budget, overlay, 1.0);  // all levels, then no further
    EXPECT_EQ(drawn(budget, overlay), overlay.boxes.size());
}

TEST(MovingBoxBudget, FramesOfUnknownTimeOrStillFramesChangeNothing) {
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    for (int i = 0; i < 5; ++i) moving_frame(budget, overlay, 0.0);  // golden images: no time
    EXPECT_EQ(drawn(budget, overlay), 4095u);
    for (int i = 0; i < 5; ++i) budget.start_frame(500.0, overlay);  // still frames: no moving overlay drawn
    EXPECT_EQ(drawn(budget, overlay), 4095u);
    // A slow moving frame, a still one, a slow moving one: not two in a row.
    moving_frame(budget, overlay, 500.0);
    budget.start_frame(500.0, overlay);
    moving_frame(budget, overlay, 500.0);
    EXPECT_EQ(drawn(budget, overlay), 4095u);
}

TEST(MovingBoxBudget, AFrameTimeGrowingWithTheBoxesSettlesOnOneLevel) {
    // 20 ms for the mesh and the panels, 6 us a box: 4095 boxes 44.6 ms (over the
    // target), 2047 boxes 32.3 ms (under it): the budget settles on 2047 for good.
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    std::vector<size_t> seen;
    for (int i = 0; i < 60; ++i) {
        const size_t boxes = drawn(budget, overlay);
        seen.push_back(boxes);
        moving_frame(budget, overlay, 20.0 + 0.006 * double(boxes));
    }
    for (size_t i = 2; i < seen.size(); ++i) EXPECT_EQ(seen[i], 2047u) << "frame " << i;
    // An octree's levels (1, 8, 64, 512, 4096, 32768): a level eight times bigger is
    // taken only if eight times the frame fits. 2 ms and 3 us a box: 585 boxes 3.8 ms
    // (eight times: 30 ms, so 4681 are taken), 4681 boxes 16 ms (eight times: 128 ms).
    StructureOverlay octree;
    for (size_t end : {1, 9, 73, 585, 4681, 37449}) octree.level_ends.push_back(end);
    octree.boxes.resize(37449);
    MovingBoxBudget octree_budget = following(octree);
    ASSERT_EQ(drawn(octree_budget, octree), 585u);  // the start budget: 4681 are more
    for (int i = 0; i < 60; ++i)
        moving_frame(octree_budget, octree, 2.0 + 0.003 * double(drawn(octree_budget, octree)));
    EXPECT_EQ(drawn(octree_budget, octree), 4681u);
}

TEST(MovingBoxBudget, ALevelGivenUpIsTakenAgainWhenTheFramesGetFasterInProportion) {
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    moving_frame(budget, overlay, 60.0);  // a busy machine: 4095 boxes in 60 ms
    moving_frame(budget, overlay, 60.0);
    ASSERT_EQ(drawn(budget, overlay), 2047u);
    moving_frame(budget, overlay, 36.0);  // without the level: 36 ms, so 4095 boxes ~ 60 ms
    moving_frame(budget, overlay, 36.0);
    EXPECT_EQ(drawn(budget, overlay), 2047u);
    // 21 ms now: 4095 boxes ~ 60 * 21 / 36 = 35 ms, though twice the frame (42 ms) is not.
    moving_frame(budget, overlay, 21.0);
    moving_frame(budget, overlay, 21.0);
    EXPECT_EQ(drawn(budget, overlay), 4095u);
}

TEST(MovingBoxBudget, AnotherOverlayStartsAgainAndAGridHasNoLevelsToFollow) {
    const StructureOverlay small = binary_levels(15), big = binary_levels(20);
    MovingBoxBudget budget = following(small);
    for (int i = 0; i < 20; ++i) moving_frame(budget, small, 1.0);  // a small fast scene: every level
    ASSERT_EQ(drawn(budget, small), small.boxes.size());
    budget.start_frame(0.0, big);  // a new scene: its first frame starts from the start budget
    EXPECT_EQ(budget.boxes(), MovingBoxBudget::kStartBoxes);
    EXPECT_EQ(drawn(budget, big), 4095u);
    // A grid: its cells have no levels and are all drawn, so slow frames change nothing.
    StructureOverlay grid;
    grid.boxes.resize(100000);
    budget.start_frame(0.0, grid);
    for (int i = 0; i < 10; ++i) moving_frame(budget, grid, 500.0);
    EXPECT_EQ(budget.boxes(), MovingBoxBudget::kStartBoxes);
}

}  // namespace
}  // namespace accelviz
