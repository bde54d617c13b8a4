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
    ASSERT_EQ(drawn(budget, overlay), 8191u);  // 13 levels at the start
    moving_frame(budget, overlay, 200.0);     // one slow frame (an upload): nothing yet
    EXPECT_EQ(drawn(budget, overlay), 8191u);
    moving_frame(budget, overlay, 30.0);  // a normal one between: counting starts again
    moving_frame(budget, overlay, 60.0);
    EXPECT_EQ(drawn(budget, overlay), 8191u);
    moving_frame(budget, overlay, 60.0);
    EXPECT_EQ(drawn(budget, overlay), 4095u);
    for (int i = 0; i < 20; ++i) moving_frame(budget, overlay, 500.0);  // however slow: never under the floor
    EXPECT_EQ(drawn(budget, overlay), 1023u);
    EXPECT_GE(budget.boxes(), MovingBoxBudget::kFewestBoxes);
}

TEST(MovingBoxBudget, FramesWithRoomForTheNextLevelTakeIt) {
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    moving_frame(budget, overlay, 10.0);  // 8191 boxes in 10 ms: 16383 would fit even at 2x
    EXPECT_EQ(drawn(budget, overlay), 8191u);
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
    EXPECT_EQ(drawn(budget, overlay), 8191u);
    for (int i = 0; i < 5; ++i) budget.start_frame(500.0, overlay);  // still frames: no moving overlay drawn
    EXPECT_EQ(drawn(budget, overlay), 8191u);
    // A slow moving frame, a still one, a slow moving one: not two in a row.
    moving_frame(budget, overlay, 500.0);
    budget.start_frame(500.0, overlay);
    moving_frame(budget, overlay, 500.0);
    EXPECT_EQ(drawn(budget, overlay), 8191u);
}

TEST(MovingBoxBudget, AFrameTimeGrowingWithTheBoxesSettlesOnOneLevel) {
    // 20 ms for the mesh and the panels, 3 us a box: 8191 boxes 44.6 ms (over the
    // target), 4095 boxes 32.3 ms (under it): the budget settles on 4095 for good.
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    std::vector<size_t> seen;
    for (int i = 0; i < 60; ++i) {
        const size_t boxes = drawn(budget, overlay);
        seen.push_back(boxes);
        moving_frame(budget, overlay, 20.0 + 0.003 * double(boxes));
    }
    for (size_t i = 2; i < seen.size(); ++i) EXPECT_EQ(seen[i], 4095u) << "frame " << i;
    // An octree's levels (1, 8, 64, 512, 4096, 32768): a level eight times bigger is
    // taken only if eight times the frame fits.
    StructureOverlay octree;
    for (size_t end : {1, 9, 73, 585, 4681, 37449}) octree.level_ends.push_back(end);
    octree.boxes.resize(37449);
    MovingBoxBudget octree_budget = following(octree);
    for (int i = 0; i < 60; ++i)
        moving_frame(octree_budget, octree, 20.0 + 0.003 * double(drawn(octree_budget, octree)));
    EXPECT_EQ(drawn(octree_budget, octree), 4681u);  // 34 ms; 37449 boxes would take 132
}

TEST(MovingBoxBudget, ALevelGivenUpIsTakenAgainWhenTheFramesGetFasterInProportion) {
    const StructureOverlay overlay = binary_levels(17);
    MovingBoxBudget budget = following(overlay);
    moving_frame(budget, overlay, 60.0);  // a busy machine: 8191 boxes in 60 ms
    moving_frame(budget, overlay, 60.0);
    ASSERT_EQ(drawn(budget, overlay), 4095u);
    moving_frame(budget, overlay, 36.0);  // without the level: 36 ms, so 8191 boxes ~ 60 ms
    moving_frame(budget, overlay, 36.0);
    EXPECT_EQ(drawn(budget, overlay), 4095u);
    // 21 ms now: 8191 boxes ~ 60 * 21 / 36 = 35 ms, though twice the frame (42 ms) is not.
    moving_frame(budget, overlay, 21.0);
    moving_frame(budget, overlay, 21.0);
    EXPECT_EQ(drawn(budget, overlay), 8191u);
}

TEST(MovingBoxBudget, AnotherOverlayStartsAgainAndAGridHasNoLevelsToFollow) {
    const StructureOverlay small = binary_levels(15), big = binary_levels(20);
    MovingBoxBudget budget = following(small);
    for (int i = 0; i < 20; ++i) moving_frame(budget, small, 1.0);  // a small fast scene: every level
    ASSERT_EQ(drawn(budget, small), small.boxes.size());
    budget.start_frame(0.0, big);  // a new scene: its first frame starts from the start budget
    EXPECT_EQ(budget.boxes(), MovingBoxBudget::kStartBoxes);
    EXPECT_EQ(drawn(budget, big), 8191u);
    // A grid: its cells have no levels and are all drawn, so slow frames change nothing.
    StructureOverlay grid;
    grid.boxes.resize(100000);
    budget.start_frame(0.0, grid);
    for (int i = 0; i < 10; ++i) moving_frame(budget, grid, 500.0);
    EXPECT_EQ(budget.boxes(), MovingBoxBudget::kStartBoxes);
}

}  // namespace
}  // namespace accelviz
