// Mouse and keys reach the 3D view through ImGui's io, driven here frame by
// frame on a headless app: a drag in the view orbits, the wheel zooms, and a
// drag that starts on a panel (ImGui wants the mouse) leaves the camera alone.
#include <cmath>
#include <thread>

#include <gtest/gtest.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>  // key codes (ImGui 1.86 indexes io.KeysDown by them)
#include <imgui.h>

#include "app/gui/headless.h"
#include "app/gui/session.h"

namespace accelviz {
namespace {

double distance(Vec3d a, Vec3d b) { return std::sqrt(dot(a - b, a - b)); }

struct InputFixture : ::testing::Test {
    void SetUp() override {
        auto created = HeadlessApp::create(640, 400);
        ASSERT_TRUE(created) << created.error();
        app = std::move(*created);
        state.scene = "builtin:cube";
        app->session().open_scene(state, state.scene);
        while (!app->session().scene || app->session().loader.busy()) {
            app->draw(state, {});
            std::this_thread::sleep_for(std::chrono::milliseconds(2));
        }
        app->draw(state, {});
        ASSERT_TRUE(state.camera.has_value());
    }
    /// One frame with the pointer at (x, y) and the left button as given.
    void frame(float x, float y, bool left_down, float wheel = 0) {
        ImGuiIO& io = ImGui::GetIO();
        io.MousePos = ImVec2(x, y);
        io.MouseDown[0] = left_down;
        io.MouseWheel = wheel;
        app->draw(state, {});
    }
    std::unique_ptr<HeadlessApp> app;
    AppState state;
};

TEST_F(InputFixture, DragInTheViewOrbitsAroundTheTarget) {
    const CameraParams before = *state.camera;
    frame(450, 200, false);
    frame(450, 200, true);
    for (int i = 1; i <= 5; ++i) frame(450 + 10.0f * i, 200, true);
    frame(500, 200, false);
    EXPECT_NE(state.camera->eye.x, before.eye.x) << "the eye moved";
    EXPECT_NEAR(distance(state.camera->eye, state.camera->target), distance(before.eye, before.target), 1e-9);
}

TEST_F(InputFixture, WheelOverTheViewZooms) {
    const double before = distance(state.camera->eye, state.camera->target);
    frame(450, 200, false, 2.0f);
    frame(450, 200, false);
    EXPECT_LT(distance(state.camera->eye, state.camera->target), before);
}

TEST_F(InputFixture, DragStartingOnAPanelLeavesTheCameraAlone) {
    const CameraParams before = *state.camera;
    frame(100, 300, false);  // over the sidebar
    frame(100, 300, true);
    for (int i = 1; i <= 5; ++i) frame(100 + 60.0f * i, 300, true);  // ends over the view
    frame(400, 300, false);
    EXPECT_EQ(state.camera->eye.x, before.eye.x);
    EXPECT_EQ(state.camera->eye.y, before.eye.y);
    EXPECT_EQ(state.camera->eye.z, before.eye.z);
}

TEST_F(InputFixture, DragOnAWindowOverTheViewLeavesTheCameraAlone) {
    // The help window lies over the 3D view: ImGui wants the mouse there.
    state.view.show_help = true;
    for (int i = 0; i < 3; ++i) frame(450, 200, false);  // shown (auto-sized windows skip a frame), then hovered
    ASSERT_TRUE(ImGui::GetIO().WantCaptureMouse) << "the pointer should be over the help window";
    const CameraParams before = *state.camera;
    frame(450, 200, true);
    for (int i = 1; i <= 5; ++i) frame(450 + 10.0f * i, 200, true);
    frame(500, 200, false);
    EXPECT_EQ(state.camera->eye.x, before.eye.x);
    EXPECT_EQ(state.camera->eye.z, before.eye.z);
}

// [SECTION] The traversal stepper: a click picks a pixel's ray, keys step it.

TEST_F(InputFixture, StepperClickPicksThatPixelsRayAndKeysStepIt) {
    state.stepper.open = true;
    FrameLayout layout = app->draw(state, {});
    layout = app->draw(state, {});  // laid out with the stepper's panel
    const ViewRect view = layout.view_rect;
    ASSERT_FALSE(view.empty());
    const CameraParams camera = *state.camera;
    const float x = float(view.x) + 0.4f * float(view.width), y = float(view.y) + 0.6f * float(view.height);
    frame(x, y, false);
    frame(x, y, true);
    frame(x, y, false);  // press and release without moving: a click
    ASSERT_TRUE(state.stepper.ray.has_value()) << "the click picked a ray";
    const Ray expected = Camera(camera, view.width, view.height).ray(int(x) - view.x, int(y) - view.y);
    EXPECT_EQ(state.stepper.ray->origin, expected.origin);
    EXPECT_EQ(state.stepper.ray->dir, expected.dir);
    EXPECT_EQ(state.camera->eye.x, camera.eye.x) << "a click does not orbit";
    EXPECT_EQ(state.stepper.step, 0u);
    const size_t events = app->session().stepper.trace.events.size();
    ASSERT_GT(events, 2u);

    ImGuiIO& io = ImGui::GetIO();
    auto press = [&](int key) {
        io.KeysDown[key] = true;
        app->draw(state, {});
        io.KeysDown[key] = false;
        app->draw(state, {});
    };
    press(GLFW_KEY_RIGHT);
    press(GLFW_KEY_RIGHT);
    EXPECT_EQ(state.stepper.step, 2u);
    press(GLFW_KEY_LEFT);
    EXPECT_EQ(state.stepper.step, 1u);
    press(GLFW_KEY_END);
    EXPECT_EQ(state.stepper.step, events);
    press(GLFW_KEY_RIGHT);
    EXPECT_EQ(state.stepper.step, events) << "no step past the end";
    press(GLFW_KEY_HOME);
    EXPECT_EQ(state.stepper.step, 0u);
    EXPECT_EQ(app->session().stepper.step_state.steps, 0u);
}

}  // namespace
}  // namespace accelviz
