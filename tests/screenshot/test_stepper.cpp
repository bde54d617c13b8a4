// The traversal stepper in the window's frame (headless, OSMesa): golden images
// of chosen steps, each asserting that the event at that step is the one the
// golden is meant to show (so a change of traversal cannot make a golden
// silently show something else); and the stepper's event list against
// `accelviz trace --json` (the window and the JSON are twins).
#include <cstdio>
#include <functional>
#include <memory>

#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "app/gui/stepper_panel.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/stepper/stepper.h"
#include "core/traversal/event_json.h"
#include "golden.h"

namespace accelviz {
namespace {

using testing::matches_golden;

constexpr int kWidth = 1200, kHeight = 720;  // the stepper's frames (and the image the pixel is of)
// A teapot pixel whose ray, through the default KD tree, finds a hit beyond the leaf it is tested in.
constexpr int kStepKdPixelX = 640, kStepKdPixelY = 270;

/// The ray of pixel (x, y) of a kWidth x kHeight image of the scene's default
/// view: what `trace --pixel x,y` traces.
AppState stepper_state(const std::string& scene, const std::string& accel_json, int x, int y, size_t step) {
    AppState state;
    state.scene = scene;
    auto parsed = app_state_from_json(nlohmann::json::parse(accel_json));
    EXPECT_TRUE(parsed) << parsed.error();
    if (parsed) state.accel = parsed->accel;
    auto mesh = load_scene(scene);
    EXPECT_TRUE(mesh) << mesh.error();
    const CameraParams camera = default_camera(mesh->bounds());
    const Ray ray = Camera(camera, kWidth, kHeight).ray(x, y);
    state.camera = stepper_side_view(camera, ray);
    state.overlay.mesh_opacity = 0.5f;  // what `render --view step` uses
    state.stepper.open = true;
    state.stepper.ray = ray;
    state.stepper.pixel = std::array<int, 2>{x, y};
    state.stepper.step = step;
    return state;
}

/// Draws the stepper frame of `state` (as render_headless does) and hands back the app.
std::unique_ptr<HeadlessApp> draw_stepper(AppState& state) {
    auto loaded = load_and_build(state.scene, state.accel);
    EXPECT_TRUE(loaded) << loaded.error();
    if (!loaded) return nullptr;
    auto app = HeadlessApp::create(kWidth, kHeight);
    EXPECT_TRUE(app) << app.error();
    if (!app) return nullptr;
    (*app)->session().set_scene(state, std::move(*loaded), true);
    for (int i = 0; i < 3; ++i) (*app)->draw(state, FrameInput{});
    return std::move(*app);
}

/// The golden of `state`, after checking that the event at its step has `kind` (and `check` holds).
void expect_step_golden(AppState state, EventKind kind, const char* name,
                        const std::function<void(const StepperPanel&)>& check = {}) {
    auto app = draw_stepper(state);
    ASSERT_TRUE(app);
    const StepperPanel& stepper = app->session().stepper;
    const size_t step = std::min(state.stepper.step, stepper.trace.events.size());
    ASSERT_GT(step, 0u);
    const TraversalEvent& e = stepper.trace.events[step - 1];
    ASSERT_EQ(e.kind, kind) << "step " << step << " is " << describe(e) << ": pick another step for " << name;
    if (check) check(stepper);
    EXPECT_TRUE(matches_golden(app->read_colour(), name));
}

// The teapot, 4x4 segments per patch; the pixel is on the body, left of centre.
const char* kTeapot = "builtin:teapot?n=4";

TEST(StepperGolden, BvhFirstVisit) {
    // Algorithm 2: the root's box test, then the first visit (step 2).
    expect_step_golden(stepper_state(kTeapot, R"({"structure": {"type": "bvh"}})", 520, 400, 2),
                       EventKind::VisitNode, "step_bvh_first_visit", [](const StepperPanel& s) {
                           EXPECT_EQ(s.trace.events[1].node, 0u);
                           EXPECT_EQ(s.step_state.visited.size(), 1u);
                       });
}

TEST(StepperGolden, WideBvhNodeTestsItsEightChildrenTogether) {
    // An 8-wide BVH: the root node's eight children's box tests (the fourth one current),
    // all lit in the 3D view and charted side by side in the panel.
    AppState state =
        stepper_state(kTeapot, R"({"structure": {"type": "bvh", "bvh": {"width": 8}}})", 520, 400, 0);
    {
        auto mesh = load_scene(kTeapot);
        auto accel = build_accelerator(*mesh, state.accel);
        ASSERT_TRUE(accel);
        const SteppedRay r = record_ray(**accel, *state.stepper.ray);
        for (size_t i = 0; i + 4 < r.events.size() && state.stepper.step == 0; ++i)
            if (r.events[i].kind == EventKind::VisitNode && r.events[i + 1].kind == EventKind::BoxTest)
                state.stepper.step = i + 1 + 4;
        ASSERT_GT(state.stepper.step, 0u) << "no wide node visited on this ray";
    }
    expect_step_golden(state, EventKind::BoxTest, "step_wide_bvh_node", [](const StepperPanel& s) {
        const SiblingTests run = sibling_box_tests(s.trace.events, s.step_state.steps - 1);
        EXPECT_EQ(run.size(), 8u) << "the root of an 8-wide tree over 880 triangles has eight children";
    });
}

TEST(StepperGolden, BvhCullBeyondTheClosestHit) {
    AppState state = stepper_state(kTeapot, R"({"structure": {"type": "bvh"}})", 520, 400, 0);
    // The first cull beyond the closest hit on this ray.
    {
        auto mesh = load_scene(kTeapot);
        AccelConfig config = state.accel;
        auto accel = build_accelerator(*mesh, config);
        ASSERT_TRUE(accel);
        const SteppedRay r = record_ray(**accel, *state.stepper.ray);
        for (size_t i = 0; i < r.events.size() && state.stepper.step == 0; ++i)
            if (r.events[i].kind == EventKind::Cull && r.events[i].reason == CullReason::BeyondClosestHit)
                state.stepper.step = i + 1;
        ASSERT_GT(state.stepper.step, 0u) << "no cull beyond the closest hit on this ray";
    }
    expect_step_golden(state, EventKind::Cull, "step_bvh_cull_beyond_closest", [](const StepperPanel& s) {
        EXPECT_EQ(s.step_state.current->reason, CullReason::BeyondClosestHit);
        EXPECT_TRUE(s.step_state.closest.found());
        EXPECT_GT(s.step_state.current->t_enter, s.step_state.closest.t);
    });
}

TEST(StepperGolden, KdHitRejectedOutsideItsCell) {
    AppState state = stepper_state(kTeapot, R"({"structure": {"type": "kd"}})", kStepKdPixelX, kStepKdPixelY, 0);
    {
        auto mesh = load_scene(kTeapot);
        auto accel = build_accelerator(*mesh, state.accel);
        ASSERT_TRUE(accel);
        const SteppedRay r = record_ray(**accel, *state.stepper.ray);
        for (size_t i = 0; i < r.events.size() && state.stepper.step == 0; ++i)
            if (r.events[i].kind == EventKind::HitOutsideCell) state.stepper.step = i + 1;
        ASSERT_GT(state.stepper.step, 0u) << "no hit outside its cell on this ray";
    }
    expect_step_golden(state, EventKind::HitOutsideCell, "step_kd_hit_outside_cell", [](const StepperPanel& s) {
        EXPECT_EQ(s.step_state.rejected.size(), 1u);
        EXPECT_GT(s.step_state.current->t, s.step_state.current->t_exit);
    });
}

TEST(StepperGolden, FinalStateClampsPastTheEnd) {
    expect_step_golden(stepper_state(kTeapot, R"({"structure": {"type": "bvh"}})", 520, 400, 1000000),
                       EventKind::Done, "step_bvh_final", [](const StepperPanel& s) {
                           EXPECT_TRUE(s.step_state.done);
                           EXPECT_EQ(s.step_state.closest.tri, s.trace.hit.tri);
                           ASSERT_FALSE(s.compare_rows.empty());
                           for (const CompareRow& row : s.compare_rows) EXPECT_TRUE(row.agrees_with_naive) << row.label;
                       });
}

TEST(Stepper, ACompareBuildFinishingAfterTheStepperClosedLeavesNothingPending) {
    // The compare table's structures build on a worker. If the stepper closes before
    // they are done, the finished build must still be taken: pending work the window
    // never takes keeps it busy for ever (found by the survival session under ASan).
    AppState state = stepper_state(kTeapot, R"({"structure": {"type": "bvh"}})", 520, 400, 1);
    auto loaded = load_and_build(state.scene, state.accel);
    ASSERT_TRUE(loaded) << loaded.error();
    Session session;
    session.set_scene(state, std::move(*loaded), true);
    StepperPanel& stepper = session.stepper;
    stepper.update(state, session, 0.0, /*wait=*/false);  // the window's frame: the build starts
    state.stepper.open = false;
    stepper.compare_job.wait();
    ASSERT_TRUE(stepper.compare_job.has_result());
    stepper.update(state, session, 0.0, false);  // a frame with the stepper closed
    EXPECT_FALSE(stepper.has_pending_work());
}

// [SECTION] The window's events are trace --json's events

std::string run(const std::string& command) {
    std::string out;
    FILE* pipe = popen(command.c_str(), "r");
    if (!pipe) return out;
    char buffer[65536];
    size_t n;
    while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
    pclose(pipe);
    return out;
}

TEST(StepperEvents, SameEventsInTheSameOrderAsTraceJson) {
    struct Case {
        const char* accel_json;
        const char* flags;
        int x, y;
    };
    const Case cases[] = {
        {R"({"structure": {"type": "bvh"}})", "--accel bvh", 520, 400},
        {R"({"structure": {"type": "bvh", "bvh": {"traversal": "unordered"}}})", "--accel bvh --bvh-traversal unordered", 600, 300},
        {R"({"structure": {"type": "grid"}})", "--accel grid", 520, 400},
        {R"({"structure": {"type": "kd"}})", "--accel kd", kStepKdPixelX, kStepKdPixelY},
        {R"({"structure": {"type": "octree"}})", "--accel octree", 700, 450},
        {R"({"structure": {"type": "naive"}})", "--accel naive", 10, 10},
    };
    for (const Case& c : cases) {
        AppState state = stepper_state(kTeapot, c.accel_json, c.x, c.y, 0);
        auto app = draw_stepper(state);
        ASSERT_TRUE(app);
        const nlohmann::json window = to_json(app->session().stepper.trace.events);
        char command[512];
        std::snprintf(command, sizeof command, "%s trace '%s' --pixel %d,%d --width %d --height %d %s --json",
                      ACCELVIZ_BINARY, kTeapot, c.x, c.y, kWidth, kHeight, c.flags);
        const std::string out = run(command);
        const nlohmann::json trace = nlohmann::json::parse(out, nullptr, false);
        ASSERT_FALSE(trace.is_discarded()) << command << "\n" << out.substr(0, 200);
        ASSERT_GT(window.size(), 1u) << c.flags;
        EXPECT_EQ(window, trace["events"]) << c.flags << " pixel " << c.x << "," << c.y;
    }
}

}  // namespace
}  // namespace accelviz
