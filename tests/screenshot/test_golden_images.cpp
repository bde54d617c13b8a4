// Golden images of the window's views, rendered headless through OSMesa with the
// same draw_frame() the window uses. Tolerance: see golden.h.
#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "golden.h"

namespace accelviz {
namespace {

using testing::matches_golden;

AppState cube_state() {
    AppState state;
    state.scene = "builtin:cube";  // default camera: the scene's default view
    return state;
}

TEST(GoldenImage, CubeStructureViewShowsShadedMeshAndBounds) {
    auto image = render_gui_view_headless(cube_state(), "structure", 320, 240);
    ASSERT_TRUE(image) << image.error();
    EXPECT_TRUE(matches_golden(*image, "cube_structure"));
}

TEST(GoldenImage, CubeGuiFrameShowsPanelsStatusAndView) {
    auto image = render_gui_view_headless(cube_state(), "gui", 640, 400);
    ASSERT_TRUE(image) << image.error();
    EXPECT_TRUE(matches_golden(*image, "cube_gui"));
}

TEST(GoldenImage, CubeGuiFrameLightThemeAtProjectorScale) {
    AppState state = cube_state();
    state.view.light_theme = true;
    state.view.background = {236, 236, 232};
    state.view.ui_scale = 1.5f;
    auto image = render_gui_view_headless(state, "gui", 960, 600);
    ASSERT_TRUE(image) << image.error();
    EXPECT_TRUE(matches_golden(*image, "cube_gui_light"));
}

TEST(GoldenImage, HelpWindowListsTheShortcuts) {
    AppState state = cube_state();
    state.view.show_help = true;
    auto image = render_gui_view_headless(state, "gui", 800, 500);
    ASSERT_TRUE(image) << image.error();
    EXPECT_TRUE(matches_golden(*image, "cube_gui_help"));
}

TEST(HeadlessRender, UnknownViewIsAnErrorNamingTheViews) {
    auto image = render_gui_view_headless(cube_state(), "nosuch", 64, 64);
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().find("structure"), std::string::npos) << image.error();
}

TEST(HeadlessRender, BadSceneIsAnError) {
    AppState state;
    state.scene = "/nonexistent/scene.obj";
    auto image = render_gui_view_headless(state, "structure", 64, 64);
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().find("/nonexistent/scene.obj"), std::string::npos) << image.error();
}

}  // namespace
}  // namespace accelviz
