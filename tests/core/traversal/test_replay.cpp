// Stepping is replay: the state after k events, computed from the recorded list.
#include <gtest/gtest.h>

#include "core/accel/brute_force.h"
#include "core/traversal/replay.h"

using namespace accelviz;

namespace {
Mesh two_walls() {
    Mesh m;
    m.add_triangle({-1, -1, -2}, {1, -1, -2}, {0, 1, -2});  // id 0, farther
    m.add_triangle({-1, -1, -1}, {1, -1, -1}, {0, 1, -1});  // id 1, nearer
    m.add_triangle({5, 5, 5}, {6, 5, 5}, {5, 6, 5});        // id 2, off to the side
    return m;
}
}  // namespace

TEST(Replay, FinalStateEqualsTheFastPathsAnswer) {
    const BruteForce bf(two_walls());
    const Ray ray{{0, 0, 0}, {0, 0, -1}};
    RecordingObserver rec;
    const Hit recorded = bf.intersect_closest(ray, rec);
    NoObserver none;
    const Hit fast = bf.intersect_closest(ray, none);
    EXPECT_EQ(recorded.tri, fast.tri);
    EXPECT_EQ(recorded.t, fast.t);

    const StepState end = replay(rec.events, rec.events.size());
    EXPECT_TRUE(end.done);
    EXPECT_EQ(end.closest.tri, 1u);
    EXPECT_EQ(end.closest.t, fast.t);
    EXPECT_EQ(end.counters, rec.counters());
    EXPECT_EQ(end.tested.size(), 3u);
}

TEST(Replay, IntermediateStepsShowTheClosestSoFar) {
    const BruteForce bf(two_walls());
    RecordingObserver rec;
    bf.intersect_closest(Ray{{0, 0, 0}, {0, 0, -1}}, rec);
    // events: test 0 (hit), new closest 0, test 1 (hit), new closest 1, test 2 (miss), done
    ASSERT_EQ(rec.events.size(), 6u);
    EXPECT_FALSE(replay(rec.events, 0).current.has_value());
    EXPECT_EQ(replay(rec.events, 2).closest.tri, 0u);
    EXPECT_EQ(replay(rec.events, 4).closest.tri, 1u);
    EXPECT_FALSE(replay(rec.events, 5).done);
    EXPECT_EQ(replay(rec.events, 5).last_triangle_test->tri, 2u);
    // Stepping back is replaying fewer events.
    EXPECT_EQ(replay(rec.events, 3).tested.size(), 2u);
    EXPECT_EQ(replay(rec.events, 1000).steps, 6u);
}

TEST(Replay, StackFollowsPushAndPop) {
    std::vector<TraversalEvent> ev;
    ev.push_back({.kind = EventKind::Push, .node = 4, .t_enter = 1});
    ev.push_back({.kind = EventKind::Push, .node = 7, .t_enter = 2});
    ev.push_back({.kind = EventKind::Pop, .node = 7, .t_enter = 2});
    ev.push_back({.kind = EventKind::Cull, .reason = CullReason::BeyondClosestHit, .node = 9, .t_enter = 5});
    const StepState s = replay(ev, ev.size());
    ASSERT_EQ(s.stack.size(), 1u);
    EXPECT_EQ(s.stack[0].node, 4u);
    ASSERT_EQ(s.culled.size(), 1u);
    EXPECT_EQ(s.culled[0].reason, CullReason::BeyondClosestHit);
    EXPECT_EQ(replay(ev, 2).stack.size(), 2u);
}
