// The text over the 3D view (view_labels.h) at every window size from 640x360 to
// 3840x2160: no label covers another, each stays inside its half of the view, and
// the labels that say what a half shows are there. Read from ImGui's own windows
// after real frames of the headless app (the same draw_frame as the window).
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include <gtest/gtest.h>
#include <imgui.h>
#include <imgui_internal.h>

#include "app/gui/headless.h"
#include "app/gui/session.h"

namespace accelviz {
namespace {

namespace fs = std::filesystem;

/// The label windows of view_labels.cpp, and the half each belongs to.
struct LabelWindow {
    const char* name;
    bool in_ray_half;
};
constexpr LabelWindow kLabels[] = {{"##raster_label", false}, {"##legend", false}, {"##preset_caption", false},
                                   {"##ray_label", true},     {"##ray_legend", true}};

struct Box {
    float x0, y0, x1, y1;
    bool overlaps(const Box& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
    bool inside(const ViewRect& r) const {
        return x0 >= float(r.x) && y0 >= float(r.y) && x1 <= float(r.x + r.width) && y1 <= float(r.y + r.height);
    }
};

/// The label windows drawn in the last frame, by name.
std::map<std::string, Box> drawn_labels() {
    std::map<std::string, Box> out;
    for (const LabelWindow& label : kLabels)
        if (const ImGuiWindow* w = ImGui::FindWindowByName(label.name); w && w->WasActive && !w->Hidden)
            out[label.name] = {w->Pos.x, w->Pos.y, w->Pos.x + w->Size.x, w->Pos.y + w->Size.y};
    return out;
}

/// A preset directory of one preset: the split view with a heat map and the grid's legend.
std::string one_preset_dir() {
    const fs::path dir = fs::path(ACCELVIZ_SCREENSHOT_OUT) / "label_presets";
    fs::create_directories(dir);
    std::ofstream(dir / "01-heat.json")
        << R"({"title": "Uniform grid, teapot: the triangle tests per pixel of a long title that wraps",
               "scene": "builtin:teapot?n=4", "structure": {"type": "grid"},
               "view": {"mode": "split", "right_view": "heat-tris"}})";
    return dir.string();
}

/// Draws `state` (a preset loaded on top when `preset`) until the scene is shown,
/// then checks the labels of the last frame.
void expect_labels_laid_out(AppState state, int width, int height, bool preset, std::vector<std::string> expected) {
    SCOPED_TRACE(std::to_string(width) + "x" + std::to_string(height));
    auto created = HeadlessApp::create(width, height);
    ASSERT_TRUE(created) << created.error();
    HeadlessApp& app = **created;
    Session& session = app.session();
    if (preset) {
        session.presets.set_dir(one_preset_dir());
        session.presets.step(+1, state, session);
    } else {
        session.open_scene(state, state.scene);
    }
    for (int i = 0; i < 2000 && (!session.scene || session.loader.busy()); ++i) {
        app.draw(state, {});
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    FrameLayout layout;
    for (int i = 0; i < 3; ++i) layout = app.draw(state, {});  // auto-sized windows settle on the second frame

    const ViewRect gl = layout.view_rect;
    const bool split = state.view.mode == ViewMode::Split;
    const ViewRect ray = {gl.x + gl.width, gl.y, gl.width, gl.height};
    const auto labels = drawn_labels();
    for (const std::string& name : expected) EXPECT_TRUE(labels.count(name)) << name << " is not drawn";
    for (const LabelWindow& label : kLabels) {
        const auto it = labels.find(label.name);
        if (it == labels.end()) continue;
        EXPECT_TRUE(it->second.inside(label.in_ray_half && split ? ray : gl))
            << label.name << " leaves its half: " << it->second.x0 << "," << it->second.y0 << " .. " << it->second.x1
            << "," << it->second.y1;
        for (const auto& [other, box] : labels) {
            if (other >= it->first) continue;
            EXPECT_FALSE(box.overlaps(it->second)) << label.name << " covers " << other;
        }
    }
}

constexpr std::pair<int, int> kSizes[] = {{640, 360}, {800, 450}, {1280, 720}, {1920, 1080}, {3840, 2160}};

TEST(ViewLabels, SplitHeatMapWithPresetCaptionAndLegendAtEverySize) {
    for (const auto& [w, h] : kSizes)
        expect_labels_laid_out(AppState{}, w, h, true,
                               {"##raster_label", "##legend", "##preset_caption", "##ray_label", "##ray_legend"});
}

TEST(ViewLabels, SplitDepthDifferenceAtEverySize) {
    for (const auto& [w, h] : kSizes) {
        AppState state;
        state.scene = "builtin:teapot?n=4";
        state.view.mode = ViewMode::Split;
        state.view.left_view = LeftView::RasterDepth;
        state.view.right_view = RightView::DepthDiff;
        expect_labels_laid_out(state, w, h, false, {"##raster_label", "##ray_label", "##ray_legend"});
    }
}

TEST(ViewLabels, ProjectorScaleOnASmallWindowStillFits) {
    AppState state;
    state.scene = "builtin:teapot?n=4";
    state.view.mode = ViewMode::Split;
    state.view.right_view = RightView::HeatNodes;
    state.view.ui_scale = 2.0f;
    expect_labels_laid_out(state, 1280, 720, false, {"##raster_label", "##ray_label", "##ray_legend"});
}

}  // namespace
}  // namespace accelviz
