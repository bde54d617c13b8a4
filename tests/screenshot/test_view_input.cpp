// Mouse and keys reach the 3D view through ImGui's io, driven here frame by
// frame on a headless app: a drag in the view orbits, the wheel zooms, and a
// drag that starts on a panel (ImGui wants the mouse) leaves the camera alone.
#include <cmath>
#include <thread>

#include <gtest/gtest.h>
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

}  // namespace
}  // namespace accelviz
