// The window's behaviour on bad input, driven headless frame by frame: a bad OBJ
// (dropped on the window) shows a message and keeps the previous scene.

#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "golden.h"

namespace accelviz {
namespace {

using testing::draw_until_loaded;


TEST(SceneErrors, BadObjDroppedOnWindowShowsMessageAndKeepsPreviousScene) {
    auto app = HeadlessApp::create(640, 400);
    ASSERT_TRUE(app) << app.error();
    AppState state;
    state.scene = "builtin:cube";
    (*app)->session().open_scene(state, state.scene);
    draw_until_loaded(**app, state);
    ASSERT_NE((*app)->session().scene, nullptr);
    const auto cube = (*app)->session().scene;
    const CameraParams camera_before = *state.camera;

    const std::string bad = "/nonexistent/dropped.obj";
    FrameInput drop;
    drop.dropped_paths = {bad};
    (*app)->draw(state, drop);
    draw_until_loaded(**app, state);

    EXPECT_EQ((*app)->session().scene, cube) << "the previous scene stays";
    EXPECT_EQ(state.scene, "builtin:cube");
    EXPECT_EQ(state.camera->eye.x, camera_before.eye.x);
    EXPECT_NE((*app)->session().message.find(bad), std::string::npos) << (*app)->session().message;
    EXPECT_NE((*app)->session().message.find("keeping builtin:cube"), std::string::npos);
}

TEST(SceneErrors, GoodObjPathLoadsAndResetsCamera) {
    auto app = HeadlessApp::create(320, 240);
    ASSERT_TRUE(app) << app.error();
    AppState state;
    (*app)->session().open_scene(state, "builtin:cube");
    draw_until_loaded(**app, state);
    ASSERT_NE((*app)->session().scene, nullptr);
    EXPECT_TRUE((*app)->session().message.empty());
    EXPECT_TRUE(state.camera.has_value()) << "the default view of the scene";
}

TEST(SavedState, ApplyingAStateLoadsItsSceneAndStructureAndKeepsItsCamera) {
    auto app = HeadlessApp::create(320, 240);
    ASSERT_TRUE(app) << app.error();
    AppState state;
    state.scene = "builtin:cube";
    (*app)->session().open_scene(state, state.scene);
    draw_until_loaded(**app, state);

    AppState saved;
    saved.scene = "builtin:teapot?n=2";
    saved.accel.type = AccelType::Octree;
    saved.camera = CameraParams{{0, 5, 9}, {0, 1, 0}, {0, 1, 0}, 40};
    saved.view.mode = ViewMode::Split;
    auto round_trip = app_state_from_json(to_json(saved));  // what a state file holds
    ASSERT_TRUE(round_trip) << round_trip.error();
    (*app)->session().apply_state(state, *round_trip);
    draw_until_loaded(**app, state);

    ASSERT_NE((*app)->session().scene, nullptr);
    EXPECT_EQ((*app)->session().scene->source, "builtin:teapot?n=2");
    EXPECT_EQ((*app)->session().scene->accel->name(), "octree");
    EXPECT_EQ(state.scene, "builtin:teapot?n=2");
    EXPECT_EQ(state.view.mode, ViewMode::Split);
    ASSERT_TRUE(state.camera.has_value());
    EXPECT_EQ(state.camera->eye.z, 9.0) << "the saved camera, not the scene's default";
}

TEST(Screenshot, WritesTheFrameAsDrawn) {
    auto app = HeadlessApp::create(320, 240);
    ASSERT_TRUE(app) << app.error();
    AppState state;
    state.scene = "builtin:cube";
    (*app)->session().open_scene(state, state.scene);
    draw_until_loaded(**app, state);
    const std::string path = testing::screenshot_out_dir() + "/screenshot_test.png";
    (*app)->session().screenshot_path = path;
    (*app)->draw(state, {});
    const Image drawn = (*app)->read_colour();
    auto written = read_png(path);
    ASSERT_TRUE(written) << written.error();
    EXPECT_TRUE(written->pixels == drawn.pixels);
    EXPECT_NE((*app)->session().message.find(path), std::string::npos);
    EXPECT_FALSE((*app)->session().message_is_error);
}

}  // namespace
}  // namespace accelviz
