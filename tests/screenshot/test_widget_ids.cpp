// No two widgets drawn in one frame share an ImGui ID. ImGui 1.86 does not warn:
// the second widget silently loses its clicks to the first (the Structure combo,
// labelled like its section header, could not be opened). widget_audit records
// every widget ImGui lays out (app/gui/widget_audit.h); these frames cover each
// panel in each of its forms: every structure, the split view, both steppers,
// the help window.
#include <gtest/gtest.h>
#include <imgui.h>

#include "app/gui/headless.h"
#include "app/gui/widget_audit.h"

namespace accelviz {
namespace {

class WidgetIds : public ::testing::Test {
protected:
    void SetUp() override { widget_audit::set_enabled(true); }
    void TearDown() override { widget_audit::set_enabled(false); }

    /// Renders the frame and checks its widgets' IDs.
    void expect_unique_ids(const AppState& state, WindowView view, const std::string& what) {
        auto frame = render_headless(state, view, 1600, 900, 2);
        ASSERT_TRUE(frame) << frame.error();
        EXPECT_GT(widget_audit::widgets().size(), 20u) << what << ": the audit saw no widgets";
        for (const widget_audit::Duplicate& d : widget_audit::duplicates())
            ADD_FAILURE() << what << ": two widgets share an ID in " << d.window << ": \"" << d.label << "\"";
    }
};

TEST_F(WidgetIds, TheAuditFindsTwoWidgetsWithOneLabel) {
    ImGuiContext* context = ImGui::CreateContext();
    ImGuiIO& io = ImGui::GetIO();
    io.IniFilename = nullptr;
    io.DisplaySize = ImVec2(400, 300);
    unsigned char* pixels = nullptr;
    int w = 0, h = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &w, &h);
    bool a = false, b = false;
    widget_audit::begin_frame();
    ImGui::NewFrame();
    ImGui::Begin("panel");
    ImGui::Checkbox("Mailbox", &a);
    ImGui::Checkbox("Mailbox", &b);      // same label, same ID: the bug
    ImGui::Checkbox("Mailbox##2", &b);   // same text, its own ID
    ImGui::End();
    ImGui::EndFrame();
    ImGui::DestroyContext(context);
    ASSERT_EQ(widget_audit::duplicates().size(), 1u);
    EXPECT_EQ(widget_audit::duplicates()[0].label, "Mailbox");
    EXPECT_EQ(widget_audit::duplicates()[0].window, "panel");
    EXPECT_EQ(widget_audit::visible_text("Mailbox##2"), "Mailbox");
}

TEST_F(WidgetIds, SidebarOfEveryStructureHasUniqueIds) {
    for (const AccelType type :
         {AccelType::Naive, AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree, AccelType::Bsp}) {
        AppState state;
        state.scene = "builtin:teapot?n=4";
        state.accel.type = type;
        expect_unique_ids(state, WindowView::Gui, "sidebar with " + std::string(to_string(type)));
    }
}

TEST_F(WidgetIds, SplitViewHelpAndLightThemeHaveUniqueIds) {
    AppState state;
    state.scene = "builtin:teapot?n=4";
    state.view.mode = ViewMode::Split;
    state.view.right_view = RightView::HeatNodes;
    state.view.show_help = true;
    state.view.light_theme = true;
    expect_unique_ids(state, WindowView::Gui, "split view with help");
}

TEST_F(WidgetIds, TraversalStepperHasUniqueIds) {
    AppState state;
    state.scene = "builtin:teapot?n=4";
    state.stepper.open = true;
    Ray ray;
    ray.origin = Vec3(0.0f, 1.0f, 8.0f);
    ray.dir = Vec3(0.0f, -0.1f, -1.0f);
    state.stepper.ray = ray;
    state.stepper.step = 3;  // mid-way: inspectors, stack
    expect_unique_ids(state, WindowView::Step, "stepper mid-way");
    state.stepper.step = 100000;  // the end: the compare table first
    expect_unique_ids(state, WindowView::Step, "stepper at the end");
}

TEST_F(WidgetIds, ConstructionStepperHasUniqueIds) {
    AppState state;
    state.scene = "builtin:teapot?n=4";
    state.build_step.active = true;
    state.build_step.step = 0;
    expect_unique_ids(state, WindowView::BuildStep, "construction stepper");
}

}  // namespace
}  // namespace accelviz
