// Events, counters and hits as JSON (trace --json): the fields each kind uses, and
// non-finite numbers as strings (JSON has no infinity).
#include <gtest/gtest.h>

#include "core/accel/bvh_build.h"
#include "core/geometry/scene.h"
#include "core/traversal/event_json.h"

using namespace accelviz;

TEST(EventJson, BoxTestHasItsIntervalAndVerdict) {
    const nlohmann::json j =
        to_json(TraversalEvent{.kind = EventKind::BoxTest, .hit = true, .node = 7, .t_enter = 1.5f, .t_exit = kInfinity});
    EXPECT_EQ(j["kind"], "box_test");
    EXPECT_EQ(j["node"], 7);
    EXPECT_EQ(j["t_enter"], 1.5);
    EXPECT_EQ(j["t_exit"], "inf");
    EXPECT_EQ(j["hit"], true);
    EXPECT_FALSE(j.contains("tri"));
}

TEST(EventJson, CullNamesItsReason) {
    const nlohmann::json j = to_json(TraversalEvent{.kind = EventKind::Cull, .reason = CullReason::BeyondClosestHit,
                                                    .node = 3, .t_enter = 2, .t_exit = 3});
    EXPECT_EQ(j["reason"], "beyond_closest_hit");
}

TEST(EventJson, MissAndHit) {
    EXPECT_EQ(to_json(Hit{}), nlohmann::json({{"hit", false}}));
    const nlohmann::json hit = to_json(Hit{4, 0.25f, 0.5f, 0.125f});
    EXPECT_EQ(hit["tri"], 4);
    EXPECT_EQ(hit["t"], 0.25);
    const nlohmann::json done = to_json(TraversalEvent{.kind = EventKind::Done});
    EXPECT_TRUE(done["tri"].is_null());
    EXPECT_EQ(done["t"], "inf");
}

TEST(EventJson, FloatsReadBackExactly) {
    const float t = 0.1f;
    EXPECT_EQ(float_to_json(t).get<double>(), double(t));
    EXPECT_EQ(float_to_json(-kInfinity), "-inf");
}

TEST(EventJson, ARecordedBvhTraceBecomesAnArrayEndingInDone) {
    auto mesh = load_scene("builtin:teapot?n=2");
    ASSERT_TRUE(mesh.ok());
    const Bvh bvh = *build_bvh(*mesh, {});
    RecordingObserver recorder;
    const Hit hit = bvh.intersect_closest(Ray{{0, 0.4f, 3}, {0, 0, -1}}, recorder);
    const nlohmann::json events = to_json(recorder.events);
    ASSERT_EQ(events.size(), recorder.events.size());
    EXPECT_EQ(events.front()["kind"], "box_test");
    EXPECT_EQ(events.back()["kind"], "done");
    EXPECT_EQ(events.back()["hit"], hit.found());
    const nlohmann::json counters = to_json(recorder.counters());
    EXPECT_EQ(counters["nodes_visited"], recorder.counters().nodes_visited);
}

TEST(EventJson, LeafCarriesItsIntervalOnTheRay) {
    const nlohmann::json j = to_json(TraversalEvent{.kind = EventKind::Leaf, .node = 5, .first = 10, .count = 3,
                                                    .t_enter = 0.5f, .t_exit = 2.0f});
    EXPECT_EQ(j["kind"], "leaf");
    EXPECT_EQ(j["count"], 3);
    EXPECT_EQ(j["t_enter"], 0.5);
    EXPECT_EQ(j["t_exit"], 2.0);
}
