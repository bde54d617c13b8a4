// Golden images of the window's views, rendered headless through OSMesa with the
// same draw_frame() the window uses. Tolerance: see golden.h.
#include <gtest/gtest.h>

#include <cstdlib>

#include "app/gui/app_state.h"
#include "app/gui/headless.h"
#include "app/gui/session.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/measure/comparison.h"
#include "core/measure/scaling.h"
#include "core/render/chart.h"
#include "core/render/ray_caster.h"
#include "core/render/views.h"
#include "golden.h"

namespace accelviz {
namespace {

using testing::matches_golden;
using testing::view_matches_golden;

AppState cube_state() {
    AppState state;
    state.scene = "builtin:cube";  // default camera: the scene's default view
    return state;
}

TEST(GoldenImage, CubeStructureViewShowsShadedMeshAndBounds) {
    EXPECT_TRUE(view_matches_golden(cube_state(), WindowView::Structure, 320, 240, "cube_structure"));
}

TEST(GoldenImage, CubeGuiFrameShowsPanelsStatusAndView) {
    EXPECT_TRUE(view_matches_golden(cube_state(), WindowView::Gui, 640, 400, "cube_gui"));
}

TEST(GoldenImage, CubeGuiFrameLightThemeAtProjectorScale) {
    AppState state = cube_state();
    state.view.light_theme = true;
    state.view.background = {236, 236, 232};
    state.view.ui_scale = 1.5f;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 960, 600, "cube_gui_light"));
}

TEST(GoldenImage, HelpWindowListsTheShortcuts) {
    AppState state = cube_state();
    state.view.show_help = true;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 800, 500, "cube_gui_help"));
}

// [SECTION] Structure overlays (the teapot, 4x4 segments per patch: small and
// with a clear shape). Each golden is the "structure" view at 320x240.

AppState teapot_with(const char* structure_json) {
    AppState state;
    state.scene = "builtin:teapot?n=4";
    auto parsed = app_state_from_json(nlohmann::json::parse(structure_json));
    EXPECT_TRUE(parsed) << parsed.error();
    if (parsed) {
        state.accel = parsed->accel;
        state.overlay = parsed->overlay;
    }
    return state;
}

void expect_structure_golden(const char* structure_json, const char* name) {
    EXPECT_TRUE(view_matches_golden(teapot_with(structure_json), WindowView::Structure, 320, 240, name));
}

TEST(GoldenImage, BvhBoxesColouredByDepth) {
    expect_structure_golden(R"({"structure": {"type": "bvh"}})", "teapot_bvh_all_levels");
}

TEST(GoldenImage, BvhOneLevelOnly) {
    expect_structure_golden(R"({"structure": {"type": "bvh"}, "overlay": {"level_min": 3, "level_max": 3}})",
                            "teapot_bvh_level3");
}

TEST(GoldenImage, BvhLeavesThroughTranslucentMesh) {
    expect_structure_golden(
        R"({"structure": {"type": "bvh"}, "overlay": {"leaves_only": true, "mesh_opacity": 0.4}})",
        "teapot_bvh_leaves_xray");
}

TEST(GoldenImage, GridNonEmptyCellsByTriangleCount) {
    expect_structure_golden(R"({"structure": {"type": "grid", "grid": {"density": 2}}})", "teapot_grid_cells");
}

TEST(GoldenImage, KdSplitPlanesClippedToTheirNodes) {
    expect_structure_golden(R"({"structure": {"type": "kd"}, "overlay": {"level_min": 0, "level_max": 4}})",
                            "teapot_kd_planes");
}

TEST(GoldenImage, OctreeCellsByDepth) {
    expect_structure_golden(R"({"structure": {"type": "octree"}, "overlay": {"level_min": 0, "level_max": 4}})",
                            "teapot_octree_cells");
}

TEST(GoldenImage, ThickLinesForProjectors) {
    AppState state = teapot_with(R"({"structure": {"type": "bvh"}, "overlay": {"level_min": 2, "level_max": 5},
                                     "view": {"line_width": 3}})");
    state.view.line_width = 3;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Structure, 480, 270, "teapot_bvh_thick_lines"));
}

TEST(GoldenImage, ThickLinesClippedAtTheNearPlaneFromInsideTheScene) {
    // The eye inside the scene's bounds: box edges pass behind it and must be
    // cut at the near plane, not smeared across the image.
    AppState state = teapot_with(R"({"structure": {"type": "bvh"}, "overlay": {"level_min": 0, "level_max": 3}})");
    state.view.line_width = 3;
    state.camera = CameraParams{{-0.2, 0.6, 0.3}, {3, 0.6, 0}, {0, 1, 0}, 70};
    EXPECT_TRUE(view_matches_golden(state, WindowView::Structure, 320, 180, "teapot_inside_thick_lines"));
}

// [SECTION] Raster vs ray cast (the ray caster's picture is waited for headless)

TEST(GoldenImage, SplitRasterAndRayCastSideBySide) {
    AppState state = teapot_with(R"({"structure": {"type": "bvh"}, "overlay": {"show_structure": false}})");
    state.view.mode = ViewMode::Split;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 800, 450, "teapot_split_raycast"));
}

TEST(GoldenImage, SplitWithNodeHeatMap) {
    AppState state = teapot_with(R"({"structure": {"type": "bvh"}, "overlay": {"level_max": 3}})");
    state.view.mode = ViewMode::Split;
    state.view.right_view = RightView::HeatNodes;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 800, 450, "teapot_split_heat_nodes"));
}

// The split view's labels and the heat legend at a projector's full HD: no label runs
// into another (the legend drops its middle tick where the three would not fit).
TEST(GoldenImage, SplitTriangleHeatAt1920x1080) {
    AppState state = teapot_with(R"({"structure": {"type": "grid"}})");
    state.view.mode = ViewMode::Split;
    state.view.right_view = RightView::HeatTris;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 1920, 1080, "teapot_split_heat_tris_1920x1080"));
}

// The light's shadow rays' work per pixel in the split view (the mirror Cornell box of
// preset 40): the label names the rays, and adds their counts to the camera rays'.
TEST(GoldenImage, SplitShadowRayHeatOfTheMirrorCornellBox) {
    auto state = load_app_state_file(std::string(ACCELVIZ_SOURCE_DIR) + "/assets/presets/40-shadows-and-reflections.json");
    ASSERT_TRUE(state) << state.error();
    state->view.right_view = RightView::HeatNodes;
    state->view.heat_rays = HeatRays::Shadow;
    EXPECT_TRUE(view_matches_golden(*state, WindowView::Gui, 1280, 720, "cornell_mirror_split_shadow_heat_nodes"));
}

// The window's split view at the smallest size the labels are laid out for (they
// wrap and cut to fit: see view_labels.h) and at a projector's full HD.
TEST(GoldenImage, SplitRayCastAt640x360) {
    AppState state = teapot_with(R"({"structure": {"type": "bvh"}, "overlay": {"level_max": 2}})");
    state.view.mode = ViewMode::Split;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 640, 360, "teapot_split_raycast_640x360"));
}

TEST(GoldenImage, SplitRayCastAt1920x1080) {
    AppState state = teapot_with(R"({"structure": {"type": "bvh"}, "overlay": {"level_max": 2}})");
    state.view.mode = ViewMode::Split;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 1920, 1080, "teapot_split_raycast_1920x1080"));
}

TEST(GoldenImage, SplitTriangleHeatAt640x360) {
    AppState state = teapot_with(R"({"structure": {"type": "grid"}})");
    state.view.mode = ViewMode::Split;
    state.view.right_view = RightView::HeatTris;
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 640, 360, "teapot_split_heat_tris_640x360"));
}

// [SECTION] The CPU views of `accelviz render` (core/render/views.h): text drawn
// into the image, at 640x360 and 1920x1080.

struct CpuFrames {
    Frame raster, ray;
    WorkSummary work;
};

CpuFrames cpu_frames(int width, int height) {
    CpuFrames out;
    auto mesh = load_scene("builtin:teapot?n=4");
    EXPECT_TRUE(mesh) << mesh.error();
    AccelConfig config;
    config.type = AccelType::Grid;
    auto accel = build_accelerator(*mesh, config);
    EXPECT_TRUE(accel) << accel.error();
    const Camera camera(CameraParams{{2.2, 1.6, 3.4}, {0, 0.45, 0}, {0, 1, 0}, 45}, width, height);
    out.ray = ray_cast(**accel, *mesh, camera, {.threads = 0, .count_work = true});
    out.raster = rasterize(*mesh, camera, &out.work.raster_work);
    out.work.accel_name = "grid";
    out.work.ray_work = out.ray.work;
    out.work.ray_work_counted = true;
    return out;
}

TEST(GoldenImage, CpuSplitAndHeatViewsAt640x360And1920x1080) {
    for (const auto& [w, h] : {std::pair{640, 360}, std::pair{1920, 1080}}) {
        const CpuFrames f = cpu_frames(w, h);
        const std::string size = std::to_string(w) + "x" + std::to_string(h);
        EXPECT_TRUE(matches_golden(split_view(f.raster, f.ray, f.work), "cpu_split_" + size));
        EXPECT_TRUE(matches_golden(heat_view(f.ray.tests, w, h, "Triangles tested per pixel (grid)", 0),
                                   "cpu_heat_tris_" + size));
        EXPECT_TRUE(matches_golden(depth_diff_view(f.raster, f.ray), "cpu_depth_diff_" + size));
    }
}

// [SECTION] Errors

/// `state`'s `view` at width x height, with the comparison's ticking clock, and in
/// lecture mode when `lecture`.
::testing::AssertionResult comparison_matches_golden(const AppState& state, WindowView view, int width, int height,
                                                     bool lecture, const std::string& name) {
    auto render = render_headless(state, view, width, height, 1, [lecture](Session& session) {
        testing::use_ticking_clock(session);
        session.lecture.on = lecture;
    });
    if (!render) return ::testing::AssertionFailure() << render.error();
    return matches_golden(render->colour, name);
}

TEST(GoldenImage, ComparisonPanelTableAndAmortizationChart) {
    // The table's eight columns and the log-log chart with its break-even dots, at a
    // desk's size (times from the ticking clock: use_ticking_clock).
    AppState state;
    state.scene = "builtin:teapot";
    state.overlay.show_structure = false;
    EXPECT_TRUE(comparison_matches_golden(state, WindowView::Comparison, 1600, 900, false, "comparison_1600x900"));
}

TEST(GoldenImage, ComparisonPanelInLectureModeAtProjectorScale) {
    AppState state;
    state.scene = "builtin:stadium";
    state.accel.type = AccelType::Grid;
    state.comparison.open = true;
    EXPECT_TRUE(comparison_matches_golden(state, WindowView::Gui, 1920, 1080, true, "comparison_lecture_1920x1080"));
}

TEST(GoldenImage, TwoBvhsPanelInLectureModeAtProjectorScale) {
    // The lecture's 22 triangles, median against binned SAH, as a lecturer shows them.
    auto state = load_app_state_file(std::string(ACCELVIZ_SOURCE_DIR) + "/assets/presets/15-bvh-two-trees.json");
    ASSERT_TRUE(state) << state.error();
    EXPECT_TRUE(comparison_matches_golden(*state, WindowView::Gui, 1920, 1080, true, "two_bvhs_lecture_1920x1080"));
}

TEST(HeadlessRender, WindowViewNamesParseBackToTheirViews) {
    for (const auto& [view, name] : kWindowViewNames.entries) EXPECT_EQ(kWindowViewNames.parse(name), view) << name;
    EXPECT_FALSE(kWindowViewNames.parse("nosuch"));
}

TEST(HeadlessRender, StepViewWithoutARayIsAnError) {
    auto image = render_gui_view_headless(cube_state(), WindowView::Step, 64, 64);
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().find("no ray"), std::string::npos) << image.error();
}

TEST(HeadlessRender, BadSceneIsAnError) {
    AppState state;
    state.scene = "/nonexistent/scene.obj";
    auto image = render_gui_view_headless(state, WindowView::Structure, 64, 64);
    ASSERT_FALSE(image);
    EXPECT_NE(image.error().find("/nonexistent/scene.obj"), std::string::npos) << image.error();
}

TEST(GoldenImage, StatsPanelShowsTheLeafSizeHistogram) {
    // A tall frame at a small UI scale, so that the Stats section (last in the sidebar) is on it.
    auto app = HeadlessApp::create(560, 1160);
    ASSERT_TRUE(app) << app.error();
    AppState state;
    state.scene = "builtin:teapot?n=4";
    state.accel.type = AccelType::Kd;
    state.view.ui_scale = 0.75f;
    auto loaded = load_and_build(state.scene, state.accel);
    ASSERT_TRUE(loaded) << loaded.error();
    Session& session = (*app)->session();
    session.set_scene(state, *loaded, false);
    session.stats_panel.open_at_start = true;
    for (int i = 0; i < 2; ++i) (*app)->draw(state, FrameInput{});  // ImGui sizes new windows on the first frame
    EXPECT_TRUE(matches_golden((*app)->read_colour(), "teapot_kd_gui_stats_histogram"));
}

/// The whole state from JSON, on the small teapot.
AppState teapot_state(const char* json) {
    auto parsed = app_state_from_json(nlohmann::json::parse(json));
    EXPECT_TRUE(parsed) << parsed.error();
    AppState state = parsed ? *parsed : AppState{};
    state.scene = "builtin:teapot?n=4";
    return state;
}

TEST(GoldenImage, SplitCpuRasterDepthNextToRayCastDepthDifference) {
    // Left: the core rasterizer's depth as grey; right: where it and the ray caster disagree.
    AppState state = teapot_state(R"({"structure": {"type": "bvh"}, "overlay": {"show_structure": false},
                                      "view": {"mode": "split", "left_view": "raster-depth", "right_view": "depth-diff"}})");
    EXPECT_TRUE(view_matches_golden(state, WindowView::Gui, 800, 400, "teapot_gui_split_depth_diff"));
}

TEST(GoldenImage, LineChartOfFixedSeriesWithItsMark) {
    // bench-motion --chart's drawing, on figures that do not depend on the machine.
    LineChart chart;
    chart.title = "SAH cost over the period";
    chart.x_label = "time t";
    chart.y_label = "SAH cost";
    chart.series.push_back({"bvh refit", {220, 110, 40}, {0, 0.25, 0.5, 0.75, 1}, {34.6, 43.3, 47.4, 42.6, 34.6}});
    chart.series.push_back({"bvh rebuild", {40, 110, 200}, {0, 0.25, 0.5, 0.75, 1}, {34.6, 34.2, 34.8, 34.3, 34.6}});
    chart.mark_x = 0.25;
    chart.mark_label = "a rebuild pays from here";
    Image image(640, 360);
    draw_line_chart(image, 0, 0, 640, 360, chart);
    // Both lines and the mark are drawn; the refit line (its peak, 47.4) rises above the rebuild's.
    auto highest_row = [&](Rgb c) {
        for (int y = 0; y < image.height; ++y)
            for (int x = 0; x < image.width; ++x)
                if (image.at(x, y) == c) return y;
        return image.height;
    };
    EXPECT_LT(highest_row({220, 110, 40}), highest_row({40, 110, 200}));
    EXPECT_LT(highest_row({200, 60, 60}), image.height) << "the mark";
    EXPECT_TRUE(testing::matches_golden(image, "line_chart"));
}

TEST(GoldenImage, ScalingChartOnLogLogAxes) {
    // render --view scaling's drawing, on figures measured once (the bunny repeated 1
    // to 128 times, 1280x720, 2 threads): rasterizing grows with the triangles, the
    // BVH's ray cast hardly.
    ScalingResult r;
    r.mesh_name = "../shared/assets/bunny.obj";
    r.structures = {bvh_config_default()};
    r.width = 1280;
    r.height = 720;
    r.threads = 2;
    const double gl[] = {23.0, 30.4, 58.4, 83.5, 145.4, 200.0, 485.1, 747.2};
    const double cpu[] = {29.4, 33.1, 57.4, 76.3, 134.8, 221.1, 623.4, 994.9};
    const double cast[] = {40.9, 41.1, 52.5, 47.2, 57.9, 50.9, 71.6, 62.8};
    for (int i = 0; i < 8; ++i) {
        ScalingPoint p;
        p.copies = uint64_t(1) << i;
        p.triangles = p.copies * 69451;
        p.gl_raster_ms = gl[i];
        p.cpu_raster_ms = cpu[i];
        p.build_ms = {0};
        p.cast_ms = {cast[i]};
        r.points.push_back(p);
    }
    const LineChart chart = scaling_chart(r);
    ASSERT_EQ(chart.series.size(), 3u);
    EXPECT_TRUE(chart.log_log);
    Image image(640, 360);
    draw_line_chart(image, 0, 0, 640, 360, chart);
    EXPECT_TRUE(testing::matches_golden(image, "scaling_chart"));
}

TEST(GoldenImage, SplitCpuRasterImageNextToRayCastDepthOnOneScale) {
    AppState state = teapot_state(R"({"structure": {"type": "kd"}, "overlay": {"show_structure": false},
                                      "view": {"mode": "split", "left_view": "raster", "right_view": "depth"}})");
    EXPECT_TRUE(view_matches_golden(state, WindowView::Structure, 480, 240, "teapot_split_raster_cpu_depth"));
}


TEST(SplitView, OpenGlDepthReadBackMatchesRayCastDepthGreyForGrey) {
    // Left: OpenGL's own z-buffer read back as t; right: the ray caster's t; both grey
    // on one scale. Away from silhouettes the two halves must be the same picture.
    AppState state = teapot_state(R"({"structure": {"type": "bvh"}, "overlay": {"show_structure": false},
                                      "view": {"mode": "split", "left_view": "opengl-depth", "right_view": "depth",
                                               "show_bounds": false}})");
    auto image = render_gui_view_headless(state, WindowView::Structure, 480, 240);
    ASSERT_TRUE(image) << image.error();
    const int half = image->width / 2;
    size_t differing = 0, covered = 0;
    // Below the labels at the top and above those at the bottom.
    for (int y = image->height / 4; y < image->height * 3 / 4; ++y)
        for (int x = 0; x < half - 1; ++x) {
            const Rgb a = image->at(x, y), b = image->at(x + half, y);
            covered += b.r > 40;  // the ray cast hit something (grey 55..255; a miss is black)
            differing += std::abs(int(a.r) - int(b.r)) > 3;
        }
    ASSERT_GT(covered, size_t(half) * image->height / 20) << "the teapot should fill part of the view";
    EXPECT_LT(double(differing), 0.02 * double(covered)) << differing << " of " << covered << " pixels differ";
}

}  // namespace
}  // namespace accelviz
