// The nearest-point stepper's model: the recorded search answers as brute force does,
// its pushes and pops balance, every skipped box lies beyond the best distance of its
// step, and the geometry of a step draws the sphere of that distance around q.
#include <cmath>

#include <gtest/gtest.h>

#include "core/accel/factory.h"
#include "test_support.h"
#include "core/geometry/scene.h"
#include "core/stepper/nearest_stepper.h"
#include "core/util/random.h"

using namespace accelviz;

namespace {

using test::build_default;

}  // namespace

TEST(NearestStepper, TheRecordedSearchIsBruteForcesAnswerAndItsStepsAreConsistent) {
    for (const char* scene : {"builtin:teapot", "builtin:same-box?n=50", "builtin:sphere?subdiv=2"}) {
        auto mesh = load_scene(scene);
        ASSERT_TRUE(mesh) << mesh.error();
        for (AccelType type : {AccelType::Bvh, AccelType::Kd, AccelType::Naive}) {
            auto accel = build_default(*mesh, type);
            ASSERT_TRUE(accel);
            const NodeBoxes boxes(*accel);
            Rng rng(7);
            const Aabb box = mesh->bounds();
            for (int i = 0; i < 40; ++i) {
                const Vec3d q = i == 0 ? default_query_point(box)
                                       : Vec3d{rng.uniform(-2.0f, 2.0f), rng.uniform(-2.0f, 2.0f), rng.uniform(-2.0f, 2.0f)};
                auto search = record_nearest(*accel, *mesh, q);
                ASSERT_TRUE(search) << search.error();
                NoObserver none;
                const NearestPoint brute = nearest_point_brute_force(*mesh, q, none);
                EXPECT_EQ(search->result.tri, brute.tri) << scene << " " << to_string(type);
                EXPECT_EQ(search->result.distance_squared, brute.distance_squared);

                // Replayed step by step: every skipped box lies beyond the best distance
                // of that step; at the end nothing waits and the best is the answer.
                const auto& events = search->events;
                float best = kInfinity;
                int pushes = 0, pops = 0;
                for (const TraversalEvent& e : events) {
                    if (e.kind == EventKind::Push) ++pushes;
                    if (e.kind == EventKind::Pop) ++pops;
                    if (e.kind == EventKind::NewClosest) {
                        EXPECT_LE(e.t, best) << "the sphere never grows";
                        best = e.t;
                    }
                    if (e.kind == EventKind::Cull) {
                        EXPECT_GT(e.t_enter, best * (1.0f - 1e-6f));
                    }
                    if (e.kind == EventKind::VisitNode) {
                        EXPECT_LE(e.t_enter, best * (1.0f + 1e-6f));
                    }
                }
                EXPECT_EQ(pushes, pops);
                const StepState end = replay(events, events.size());
                EXPECT_TRUE(end.stack.empty());
                EXPECT_TRUE(end.done);
                EXPECT_EQ(end.closest.tri, brute.tri);

                // The geometry at the end: q's cross, the sphere (three circles of its
                // radius around q) and the line to the nearest point.
                const DebugGeometry g = nearest_geometry(*search, end, boxes, *mesh);
                size_t on_sphere = 0;
                for (const DebugSegment& s : g.segments) {
                    const Vec3d d = to_double(s.a) - q;
                    if (std::abs(std::sqrt(dot(d, d)) - brute.distance()) < 1e-4 * (1 + brute.distance())) ++on_sphere;
                }
                EXPECT_GE(on_sphere, 3u * 72u) << "three great circles of the best distance";
                if (type != AccelType::Naive) {
                    EXPECT_FALSE(g.boxes.empty());
                }
            }
        }
    }
}

TEST(NearestStepper, AStructureWithoutTheSearchIsAnErrorThatSaysWhich) {
    auto mesh = load_scene("builtin:cube");
    ASSERT_TRUE(mesh);
    for (AccelType type : {AccelType::Grid, AccelType::Octree}) {
        auto accel = build_default(*mesh, type);
        ASSERT_TRUE(accel);
        auto search = record_nearest(*accel, *mesh, {2, 2, 2});
        ASSERT_FALSE(search);
        EXPECT_NE(search.error().find("answers rays only"), std::string::npos) << search.error();
    }
}

TEST(NearestStepper, EveryEventHasASentenceAndALine) {
    auto mesh = load_scene("builtin:teapot");
    ASSERT_TRUE(mesh);
    auto accel = build_default(*mesh, AccelType::Bvh);
    auto search = record_nearest(*accel, *mesh, {0.0, 0.45, 0.75});
    ASSERT_TRUE(search);
    for (size_t k = 1; k <= search->events.size(); ++k) {
        const TraversalEvent& e = search->events[k - 1];
        const StepState s = replay(search->events, k);
        EXPECT_FALSE(explain_nearest_event(e, s).empty());
        EXPECT_NE(describe_nearest_event(e).find(e.kind == EventKind::Done ? "done" : ""), std::string::npos);
    }
    const TraversalEvent& last = search->events.back();
    EXPECT_NE(explain_nearest_event(last, replay(search->events, search->events.size())).find("triangle"),
              std::string::npos);
}
