// The construction stepper in the window frame (headless, OSMesa): golden images of
// the SAH chart on the bunny and on a tricky scene, and its errors.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <thread>
#include <imgui.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes: ImGui 1.86 indexes io.KeysDown by the GLFW backend's codes

#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "core/accel/kd_tree.h"
#include "golden.h"

namespace accelviz {
namespace {

using testing::matches_golden;
using testing::view_matches_golden;

std::string bunny() { return std::string(ACCELVIZ_SHARED_ASSETS) + "/bunny.obj"; }

/// The frame right of the sidebar and above the status bar: the 3D view and the
/// Construction panel. (The sidebar and the status bar show the mesh's path, which
/// depends on where the checkout is.)
Image view_and_panel(const Image& frame) {
    const int left = 320, bottom = 40;
    Image out(frame.width - left, frame.height - bottom);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x) out.at(x, y) = frame.at(x + left, y);
    return out;
}

AppState build_step_state(const std::string& scene, BvhBuilder builder, int step) {
    AppState state;
    state.scene = scene;
    state.accel.type = AccelType::Bvh;
    state.accel.bvh.builder = builder;
    state.build_step.active = true;
    state.build_step.step = step;
    return state;
}

TEST(BuildStepGolden, BunnyBinnedSahEarlySplit) {
    // Decision 1: the root's left child, split by binned SAH (B = 16).
    if (!std::filesystem::exists(bunny())) GTEST_SKIP() << bunny() << " is not here";
    auto image = render_gui_view_headless(build_step_state(bunny(), BvhBuilder::SahBinned, 1), WindowView::BuildStep, 1280, 800);
    ASSERT_TRUE(image) << image.error();
    EXPECT_TRUE(matches_golden(view_and_panel(*image), "bunny_build_step_binned"));
}

TEST(BuildStepGolden, SameBoxChartShowsNoSplitHelps) {
    // Every triangle has the same box: every plane costs C_trav + N C_isect, above the leaf line.
    AppState state = build_step_state("builtin:same-box?n=40", BvhBuilder::SahBinned, 0);
    state.build_step.bins = 8;  // the chart's own B (live slider), not the tree's
    EXPECT_TRUE(view_matches_golden(state, WindowView::BuildStep, 1280, 800, "same_box_build_step"));
}

TEST(BuildStepHeadless, StepOutOfRangeIsAnErrorWithTheRange) {
    auto image = render_gui_view_headless(build_step_state("builtin:cube", BvhBuilder::SahBinned, 999), WindowView::BuildStep, 64, 64);
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().find("out of range"), std::string::npos) << image.error();
    EXPECT_NE(image.error().find("0.."), std::string::npos) << image.error();
}

TEST(BuildStepHeadless, NeedsABvh) {
    AppState state = build_step_state("builtin:cube", BvhBuilder::SahBinned, 0);
    state.accel.type = AccelType::Grid;
    auto image = render_gui_view_headless(state, WindowView::BuildStep, 64, 64);
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().find("BVH"), std::string::npos) << image.error();
}

TEST(BuildStepHeadless, KeysStepForwardAndBackAndTheStateRoundTrips) {
    auto app = HeadlessApp::create(320, 240);
    ASSERT_TRUE(app) << app.error();
    AppState state = build_step_state("builtin:teapot?n=2", BvhBuilder::SahBinned, 0);
    LoadResult loaded = load_and_build(state.scene, state.accel);
    ASSERT_TRUE(loaded) << loaded.error();
    (*app)->session().set_scene(state, std::move(*loaded), false);
    (*app)->draw(state, {});
    const BuildTrace* trace = (*app)->session().build_stepper.trace();
    ASSERT_TRUE(trace);
    EXPECT_EQ(trace->steps.size(), trace->bvh.nodes.size());
    auto press = [&](int key) {
        ImGuiIO& io = ImGui::GetIO();
        io.KeysDown[key] = true;
        (*app)->draw(state, {});
        io.KeysDown[key] = false;
        (*app)->draw(state, {});
    };
    press(GLFW_KEY_RIGHT);
    press(GLFW_KEY_RIGHT);
    EXPECT_EQ(state.build_step.step, 2);
    press(GLFW_KEY_LEFT);
    EXPECT_EQ(state.build_step.step, 1);
    press(GLFW_KEY_END);
    EXPECT_EQ(state.build_step.step, int(trace->steps.size()) - 1);
    press(GLFW_KEY_HOME);
    EXPECT_EQ(state.build_step.step, 0);
    // The chart's parameters and the step survive a preset.
    state.build_step.step = 3;
    state.build_step.cost_trav = 2.5f;
    auto back = app_state_from_json(to_json(state));
    ASSERT_TRUE(back) << back.error();
    EXPECT_EQ(back->build_step, state.build_step);
    EXPECT_FALSE(app_state_from_json(nlohmann::json::parse(R"({"build_step": {"bins": 1}})")));
}

TEST(BuildStepHeadless, RecordingFollowsTheSceneAndIsReleasedWhenOff) {
    auto app = HeadlessApp::create(320, 240);
    ASSERT_TRUE(app) << app.error();
    AppState state = build_step_state("builtin:teapot?n=2", BvhBuilder::SahBinned, 5);
    LoadResult loaded = load_and_build(state.scene, state.accel);
    ASSERT_TRUE(loaded) << loaded.error();
    (*app)->session().set_scene(state, std::move(*loaded), false);
    (*app)->draw(state, {});
    const BuildTrace* first = (*app)->session().build_stepper.trace();
    ASSERT_TRUE(first);
    EXPECT_EQ(first->scene, (*app)->session().scene);
    // A rebuild with another builder (a new scene object): recorded again, the step kept.
    state.accel.bvh.builder = BvhBuilder::Median;
    LoadResult rebuilt = rebuild(*(*app)->session().scene, state.accel);
    ASSERT_TRUE(rebuilt) << rebuilt.error();
    (*app)->session().set_scene(state, std::move(*rebuilt), true);
    (*app)->draw(state, {});
    const BuildTrace* second = (*app)->session().build_stepper.trace();
    ASSERT_TRUE(second);
    EXPECT_EQ(second->config.builder, BvhBuilder::Median);
    EXPECT_EQ(state.build_step.step, 5);
    // Off, and the scene changes: the recording is let go.
    state.build_step.active = false;
    LoadResult again = rebuild(*(*app)->session().scene, state.accel);
    ASSERT_TRUE(again) << again.error();
    (*app)->session().set_scene(state, std::move(*again), true);
    (*app)->draw(state, {});
    EXPECT_EQ((*app)->session().build_stepper.trace(), nullptr);
}

TEST(BuildStepHeadless, OurKdTreeIsSteppedNodeByNodeInItsBuildOrder) {
    // The KD build is not recorded decision by decision: its nodes, numbered in the order
    // the build made them, are stepped as a file's are, with each node's cell and plane.
    auto app = HeadlessApp::create(320, 240);
    ASSERT_TRUE(app) << app.error();
    AppState state;
    state.scene = "builtin:teapot";
    state.accel.type = AccelType::Kd;
    state.build_step.active = true;
    LoadResult loaded = load_and_build(state.scene, state.accel);
    ASSERT_TRUE(loaded) << loaded.error();
    (*app)->session().set_scene(state, std::move(*loaded), false);
    for (int i = 0; i < 2; ++i) (*app)->draw(state, {});
    const Session& session = (*app)->session();
    const KdTree* kd = structure_if<KdTree>(*session.scene->accel);
    ASSERT_NE(kd, nullptr);
    EXPECT_EQ(session.build_stepper.trace(), nullptr) << "no BVH build recorded";
    const FileOrderTrace* trace = session.build_stepper.file_trace();
    ASSERT_NE(trace, nullptr);
    EXPECT_EQ(trace->check, nullptr) << "our own tree: nothing to fault";
    EXPECT_EQ(trace->order.size(), kd->nodes.size());
    const FileNodeStep* root = session.build_stepper.file_node();
    ASSERT_NE(root, nullptr);
    EXPECT_EQ(root->node, 0u);
    EXPECT_EQ(root->axis, kd->nodes[0].axis());
    EXPECT_EQ(root->split, kd->nodes[0].split());
    EXPECT_EQ(root->box, kd->bounds);
    EXPECT_EQ(root->children, (std::vector<uint64_t>{kd->nodes[0].lower_child(), kd->nodes[0].upper_child()}));
    // Every node comes after its parent: the build made it when it split the parent.
    for (uint64_t n = 1; n < trace->order.size(); ++n) ASSERT_LT(trace->order.parent[n], int64_t(n)) << n;
    // The SAH chart of the root: its cheapest plane under the tree's costs is the tree's.
    const KdSahChart* chart = session.build_stepper.kd_chart();
    ASSERT_NE(chart, nullptr);
    EXPECT_EQ(chart->best_axis, kd->nodes[0].axis());
    EXPECT_EQ(chart->best_position, kd->nodes[0].split());
    EXPECT_EQ(chart->config.cost_trav, kd->build_config.cost_trav);
    // A key steps to the next node.
    ImGuiIO& io = ImGui::GetIO();
    io.KeysDown[GLFW_KEY_RIGHT] = true;
    (*app)->draw(state, {});
    io.KeysDown[GLFW_KEY_RIGHT] = false;
    for (int i = 0; i < 2; ++i) (*app)->draw(state, {});
    EXPECT_EQ(state.build_step.step, 1);
    ASSERT_NE(session.build_stepper.file_node(), nullptr);
    EXPECT_EQ(session.build_stepper.file_node()->node, 1u);
    ASSERT_NE(session.build_stepper.kd_chart(), nullptr);
    EXPECT_EQ(session.build_stepper.kd_chart()->node, 1u);
    // Off: the tree stepped is let go (with the scene it kept alive).
    state.build_step.active = false;
    (*app)->draw(state, {});
    EXPECT_EQ(session.build_stepper.file_trace(), nullptr);
    EXPECT_EQ(session.build_stepper.kd_chart(), nullptr);
}

TEST(BuildStepHeadless, WorkFinishedAfterTheStepperIsTurnedOffIsDroppedNotLeftPending) {
    // The stepper asks a worker for its tree, and is turned off before the answer
    // comes (a lecturer paging through presets): the answer is dropped when it comes,
    // so nothing waits for ever, and turned on again the stepper asks again.
    for (const AccelType type : {AccelType::Bvh, AccelType::Kd}) {
        SCOPED_TRACE(to_string(type));
        AppState state;
        state.scene = "builtin:teapot";
        state.accel.type = type;
        state.build_step.active = true;
        LoadResult loaded = load_and_build(state.scene, state.accel);
        ASSERT_TRUE(loaded) << loaded.error();
        BuildStepper stepper;
        stepper.update(state, *loaded, false);  // asks, does not wait
        state.build_step.active = false;
        stepper.update(state, *loaded, false);
        for (int i = 0; i < 3000 && stepper.busy(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        ASSERT_FALSE(stepper.busy());
        stepper.update(state, *loaded, false);  // the frame the finished work wakes
        EXPECT_FALSE(stepper.has_result()) << "a finished answer nobody takes is pending work for ever";
        EXPECT_EQ(stepper.trace(), nullptr);
        EXPECT_EQ(stepper.file_trace(), nullptr);
        state.build_step.active = true;
        stepper.update(state, *loaded, true);
        if (type == AccelType::Bvh) EXPECT_NE(stepper.trace(), nullptr);
        else EXPECT_NE(stepper.file_trace(), nullptr);
    }
}

TEST(BuildStepGolden, KdTreeNodeWithItsPlaneCellsAndSahChart) {
    AppState state;
    state.scene = "builtin:teapot";
    state.accel.type = AccelType::Kd;
    state.build_step.active = true;
    state.build_step.step = 1;
    EXPECT_TRUE(view_matches_golden(state, WindowView::BuildStep, 1000, 900, "teapot_kd_build_node1"));
}

}  // namespace
}  // namespace accelviz
