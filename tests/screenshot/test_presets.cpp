// The shipped presets (assets/presets): each one loads and renders headless, they
// sort in lecture order, PageDown / PageUp step through a list, every one has a
// golden image, and every one that steps a ray stops at the event its caption
// describes.
#include <algorithm>
#include <chrono>
#include <filesystem>
#include <optional>
#include <fstream>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "app/gui/headless.h"
#include "app/gui/comparison_panel.h"
#include "app/gui/scaling_panel.h"
#include "app/gui/two_bvhs_panel.h"
#include "app/gl/renderer.h"
#include "app/platform/osmesa_context.h"
#include "app/gui/presets.h"
#include "app/gui/scene_loader.h"
#include "app/gui/session.h"
#include "core/accel/factory.h"
#include "core/accel/kd_sah_chart.h"
#include "core/geometry/scene.h"
#include "core/measure/comparison.h"
#include "core/measure/two_bvhs.h"
#include "core/render/camera.h"
#include "core/stepper/nearest_stepper.h"
#include "core/stepper/stepper.h"
#include "golden.h"

namespace accelviz {
namespace {

namespace fs = std::filesystem;

const std::string kPresetDir = std::string(ACCELVIZ_SOURCE_DIR) + "/assets/presets";

/// A directory of preset files (name, JSON text) under the test output.
fs::path write_presets(const std::string& dir_name, const std::vector<std::pair<std::string, std::string>>& files) {
    const fs::path dir = fs::path(ACCELVIZ_SCREENSHOT_OUT) / dir_name;
    fs::create_directories(dir);
    for (const auto& [name, text] : files) std::ofstream(dir / name) << text;
    return dir;
}

/// Until the worker has finished what it was asked for.
void wait_for_loader(const Session& session) {
    while (session.loader.busy()) std::this_thread::sleep_for(std::chrono::milliseconds(5));
}

TEST(Presets, ShippedOnesAreFoundAndSortInLectureOrder) {
    EXPECT_EQ(fs::path(find_presets_dir()), fs::path(kPresetDir).lexically_normal());
    const std::vector<PresetInfo> presets = list_presets(kPresetDir);
    ASSERT_GE(presets.size(), 10u);
    for (size_t i = 0; i < presets.size(); ++i) {
        // "NN-name": two digits, numbered from 01 without gaps, so that file order is lecture order.
        char number[32];
        std::snprintf(number, sizeof number, "%02zu-", i + 1);
        EXPECT_EQ(presets[i].name.rfind(number, 0), 0u) << presets[i].name;
        EXPECT_NE(presets[i].title, presets[i].name) << presets[i].path << " has no \"title\"";
        EXPECT_FALSE(presets[i].caption.empty()) << presets[i].path << " has no \"caption\"";
    }
}

TEST(Presets, PageDownAndPageUpStepThroughTheListAndStopAtItsEnds) {
    const fs::path dir = write_presets("preset_list", {
        {"02-second.json", R"({"title": "Second", "scene": "builtin:cube", "structure": {"type": "grid"}})"},
        {"01-first.json", R"({"title": "First", "scene": "builtin:cube", "structure": {"type": "bvh"}})"},
        {"notes.txt", "not a preset"}});
    Session session;
    PresetList& list = session.presets;
    list.set_dir(dir.string());
    ASSERT_EQ(list.entries().size(), 2u);
    EXPECT_EQ(list.entries()[0].title, "First");
    AppState state;
    list.step(+1, state, session);
    EXPECT_EQ(list.current(), 0);
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
    list.step(+1, state, session);
    EXPECT_EQ(list.current(), 1);
    EXPECT_EQ(state.accel.type, AccelType::Grid);
    EXPECT_EQ(list.caption(), "Preset 2/2: Second");
    list.step(+1, state, session);  // the last one stays
    EXPECT_EQ(list.current(), 1);
    list.step(-1, state, session);
    EXPECT_EQ(list.current(), 0);
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
    wait_for_loader(session);
}

TEST(Presets, TheCaptionStaysUntilThePresetsSceneIsOnScreen) {
    // A scene that takes longer to load than the caption's few seconds: the caption
    // must still be up when it arrives (it counts from then, not from the key press).
    const fs::path dir = write_presets("preset_caption", {
        {"01-slow.json", R"({"title": "Slow", "scene": "builtin:soup?n=200000", "structure": {"type": "bvh"}})"}});
    Session session;
    session.presets.set_dir(dir.string());
    AppState state;
    session.presets.step(+1, state, session);
    ASSERT_TRUE(session.loader.busy());
    std::this_thread::sleep_for(std::chrono::milliseconds(4500));  // longer than the caption lasts
    wait_for_loader(session);
    EXPECT_TRUE(session.presets.caption_fresh()) << "the caption went before the scene came";
    session.take_finished_load(state);
    ASSERT_TRUE(session.scene);
    EXPECT_TRUE(session.presets.caption_fresh()) << "the caption went as the scene came";
}

TEST(Presets, TheWindowOpenedOnAPresetGoesOnFromIt) {
    const fs::path dir = write_presets("preset_opened_with", {
        {"01-first.json", R"({"title": "First", "scene": "builtin:cube", "structure": {"type": "bvh"}})"},
        {"02-second.json", R"({"title": "Second", "scene": "builtin:cube", "structure": {"type": "grid"}})"},
        {"elsewhere.json.txt", "{}"}});
    Session session;
    PresetList& list = session.presets;
    list.set_dir(dir.string());
    list.opened_with((dir / "elsewhere.json.txt").string(), session);  // not one of the list
    EXPECT_EQ(list.current(), -1);
    // Spelled another way than the list spells it: the same file.
    list.opened_with((dir / ".." / dir.filename() / "02-second.json").string(), session);
    EXPECT_EQ(list.current(), 1);
    EXPECT_EQ(list.caption(), "Preset 2/2: Second");
    EXPECT_TRUE(list.caption_fresh());
    AppState state;
    list.step(-1, state, session);  // PageUp goes on from it
    EXPECT_EQ(list.current(), 0);
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
    wait_for_loader(session);
}

TEST(Presets, APresetOfTheSceneOnScreenOverridesALoadStillComing) {
    // Two quick PageDowns: the first preset's scene is still loading when the second,
    // whose scene and structure are the ones on screen, is chosen. The second wins:
    // the first one's scene must not arrive under the second one's caption.
    const fs::path dir = write_presets("preset_overrides", {
        {"01-big.json", R"({"title": "Big", "scene": "builtin:soup?n=300000", "structure": {"type": "kd"}})"},
        {"02-cube.json", R"({"title": "Cube", "scene": "builtin:cube", "structure": {"type": "bvh"}})"}});
    Session session;
    AppState state;
    state.scene = "builtin:cube";
    session.open_scene(state, state.scene);
    wait_for_loader(session);
    session.take_finished_load(state);
    ASSERT_TRUE(session.scene);
    ASSERT_EQ(session.scene->accel_config.type, AccelType::Bvh);
    session.presets.set_dir(dir.string());
    session.presets.step(+1, state, session);  // 01: a 300k-triangle KD build, seconds
    ASSERT_TRUE(session.loader.busy());
    session.presets.step(+1, state, session);  // 02: what is on screen
    wait_for_loader(session);
    session.take_finished_load(state);
    EXPECT_EQ(session.presets.current(), 1);
    EXPECT_EQ(session.scene->source, "builtin:cube");
    EXPECT_EQ(session.scene->accel_config.type, AccelType::Bvh);
    EXPECT_EQ(state.scene, "builtin:cube");
    EXPECT_EQ(state.accel.type, AccelType::Bvh);
}

TEST(Presets, ABadPresetFileIsAMessageAndChangesNothing) {
    const fs::path dir = write_presets("preset_list_bad", {
        {"01-broken.json", R"({"structure": {"type": "bvh", "bvh": {"builder": "best"}}})"}});
    Session session;
    session.presets.set_dir(dir.string());
    AppState state;
    state.accel.type = AccelType::Kd;
    session.presets.step(+1, state, session);
    EXPECT_EQ(session.presets.current(), -1);
    EXPECT_EQ(state.accel.type, AccelType::Kd);
    EXPECT_NE(session.message.find("01-broken.json: structure.bvh.builder"), std::string::npos) << session.message;
}

// [SECTION] The lecture's sequence

using testing::ticking_clock;

TEST(GoldenImage, EveryShippedPresetLoadsRendersAndMatchesItsGolden) {
    // The window's frame for the preset (without the caption, whose "N/M" changes
    // when a preset is added). Checked by eye when made.
    for (const PresetInfo& preset : list_presets(kPresetDir)) {
        SCOPED_TRACE(preset.path);
        auto state = load_app_state_file(preset.path);
        ASSERT_TRUE(state) << state.error();
        auto render = render_headless(*state, WindowView::Gui, 640, 360, 1,
                                      testing::use_ticking_clock);
        ASSERT_TRUE(render) << render.error();
        const Image* image = &render->colour;
        // Right of the sidebar the frame shows something besides the background.
        std::set<uint32_t> colours;
        for (int y = 0; y < image->height; y += 2)
            for (int x = image->width / 2; x < image->width; x += 2) {
                const Rgb c = image->at(x, y);
                colours.insert(uint32_t(c.r) << 16 | uint32_t(c.g) << 8 | c.b);
            }
        EXPECT_GT(colours.size(), 20u);
        EXPECT_TRUE(testing::matches_golden(*image, "preset_" + preset.name));
    }
}

TEST(Presets, TheComparisonPresetsMeasureWhatTheirCaptionsSay) {
    // Counts, not times (those are the machine's): every structure finds naive's hits;
    // the cell structures meet triangles again, the BVH never; in the stadium the grid,
    // which cannot adapt, tests many times the triangles per ray the trees do (the KD
    // tree, whose leaves are tested four triangles at a time and priced so, several
    // times: its leaves are bigger).
    std::vector<StructureComparison> measured;
    for (const char* name : {"36-comparison-table", "37-amortization"}) {
        SCOPED_TRACE(name);
        auto state = load_app_state_file(kPresetDir + "/" + name + ".json");
        ASSERT_TRUE(state) << state.error();
        EXPECT_TRUE(state->comparison.open);
        auto mesh = load_scene(state->scene);
        ASSERT_TRUE(mesh) << mesh.error();
        const Camera camera(state->camera.value_or(default_camera(mesh->bounds())), 320, 240);
        MeasureOptions options;
        options.clock = ticking_clock();
        auto comparison = measure_structures(*mesh, camera, options);
        ASSERT_TRUE(comparison) << comparison.error();
        ASSERT_EQ(comparison->rows.size(), 5u);
        for (const StructureMeasurement& row : comparison->rows) EXPECT_EQ(row.mismatches, 0u) << row.label;
        EXPECT_GT(comparison->rows[1].repeats_per_ray, 0.0);  // grid
        EXPECT_EQ(comparison->rows[4].repeats_per_ray, 0.0);  // BVH
        measured.push_back(std::move(*comparison));
    }
    ASSERT_EQ(measured.size(), 2u);
    const auto& stadium = measured[1].rows;
    for (size_t tree : {3, 4}) EXPECT_GT(stadium[1].triangle_tests_per_ray, 10 * stadium[tree].triangle_tests_per_ray);
    EXPECT_GT(stadium[1].triangle_tests_per_ray, 4 * stadium[2].triangle_tests_per_ray);  // KD
}

TEST(Presets, TheTwoTreesPresetShowsTheSahTreeBetter) {
    // Its caption: the median split overlaps, the SAH tree is cheaper and its rays
    // visit fewer nodes; at the window's shapes from a desk to lecture mode.
    auto state = load_app_state_file(kPresetDir + "/15-bvh-two-trees.json");
    ASSERT_TRUE(state) << state.error();
    EXPECT_TRUE(state->two_bvhs.open);
    EXPECT_EQ(state->two_bvhs.builders, (std::array<BvhBuilder, 2>{BvhBuilder::Median, BvhBuilder::SahBinned}));
    auto mesh = load_scene(state->scene);
    ASSERT_TRUE(mesh) << mesh.error();
    EXPECT_EQ(mesh->triangle_count(), 22u);
    ASSERT_TRUE(state->camera);
    for (const auto& [w, h] : {std::pair{624, 872}, std::pair{160, 300}, std::pair{1114, 944}}) {
        SCOPED_TRACE(std::to_string(w) + "x" + std::to_string(h));
        auto measured = measure_two_bvhs(*mesh, Camera(*state->camera, w, h), state->accel.bvh, state->two_bvhs.builders);
        ASSERT_TRUE(measured) << measured.error();
        EXPECT_EQ(measured->disagreements, 0u);
        const auto& [median, sah] = measured->trees;
        EXPECT_LT(sah.stats.sah_cost, median.stats.sah_cost);
        EXPECT_LT(sah.nodes_per_ray, median.nodes_per_ray);
        EXPECT_LT(sah.triangle_tests_per_ray, median.triangle_tests_per_ray);
        // The scene is in view: a good share of the sampled rays reach the trees.
        EXPECT_GT(measured->rays_meeting_root, measured->rays / 20);
    }
}

TEST(TwoBvhsPanel, MeasuresAgainWhenTheBuildersChange) {
    auto loaded = load_and_build("builtin:twenty-two", AccelConfig{});
    ASSERT_TRUE(loaded) << loaded.error();
    AppState state;
    state.two_bvhs.open = true;
    state.camera = default_camera((*loaded)->bounds);
    TwoBvhsPanel panel;
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/true);
    ASSERT_NE(panel.measured(), nullptr);
    EXPECT_EQ(panel.measured()->trees[0].builder, BvhBuilder::Median);
    state.two_bvhs.builders = {BvhBuilder::SahSweep, BvhBuilder::Midpoint};
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/true);
    EXPECT_EQ(panel.measured()->trees[0].builder, BvhBuilder::SahSweep);
    EXPECT_EQ(panel.measured()->trees[1].builder, BvhBuilder::Midpoint);
    // Hidden while measuring, then shown: measured again, no error left behind.
    state.two_bvhs.builders = {BvhBuilder::Median, BvhBuilder::SahBinned};
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/false);
    panel.update(state, *loaded, 320, 240, /*shown=*/false, /*wait=*/false);
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/true);
    EXPECT_EQ(panel.measured()->trees[0].builder, BvhBuilder::Median);
    EXPECT_EQ(panel.error(), "");
    // Another camera: measured again (through the same trees).
    state.camera->eye = state.camera->eye * 1.5;
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/true);
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/true);
    ASSERT_NE(panel.measured(), nullptr);
    EXPECT_EQ(panel.measured()->trees[0].builder, BvhBuilder::Median);
    EXPECT_EQ(panel.error(), "");
}

TEST(Presets, TheTwoLoopsPresetStopsBothPartWay) {
    auto state = load_app_state_file(kPresetDir + "/38-raster-vs-raycast-loops.json");
    ASSERT_TRUE(state) << state.error();
    EXPECT_EQ(state->view.mode, ViewMode::Split);
    EXPECT_TRUE(state->view.fill_order);
    EXPECT_GT(state->view.fill, 0.0f);
    EXPECT_LT(state->view.fill, 1.0f);
}

TEST(ComparisonPanel, ClosedWhileMeasuringItMeasuresAgainWhenShownAgain) {
    auto loaded = load_and_build("builtin:teapot", AccelConfig{});
    ASSERT_TRUE(loaded) << loaded.error();
    AppState state;
    state.comparison.open = true;
    state.camera = default_camera((*loaded)->bounds);
    ComparisonPanel panel;
    panel.options.clock = ticking_clock();
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/false);
    panel.update(state, *loaded, 320, 240, /*shown=*/false, /*wait=*/false);  // closed: cancelled
    // Shown again: whether or not the first measurement got to finish, a table comes,
    // and a cancelled measurement is no error to show.
    panel.update(state, *loaded, 320, 240, /*shown=*/true, /*wait=*/true);
    ASSERT_NE(panel.measured(), nullptr);
    EXPECT_EQ(panel.measured()->rows.size(), 5u);
    EXPECT_EQ(panel.measured()->width, 320);
}

TEST(ScalingPanel, AHeadlessWaitDrawsOpenGLsFramesAndMeasuresEveryScene) {
    auto context = OsMesaContext::create(96, 54);  // the frames' size
    ASSERT_TRUE(context) << context.error();
    auto renderer = Renderer::create();
    ASSERT_TRUE(renderer) << renderer.error();
    auto loaded = load_and_build("builtin:teapot?n=4", AccelConfig{});
    ASSERT_TRUE(loaded) << loaded.error();
    AppState state;
    state.scaling.open = true;
    state.scaling.max_triangles = 4.0 * double((*loaded)->mesh->triangle_count());
    state.scaling.structures = {AccelType::Bvh, AccelType::Grid};
    ScalingPanel panel;
    panel.repeat = 1;
    // Shown, then closed at once: cancelled (no error to show), measured again when shown.
    panel.update(state, *loaded, **renderer, 96, 54, /*shown=*/true, /*wait=*/false);
    panel.update(state, *loaded, **renderer, 96, 54, /*shown=*/false, /*wait=*/false);
    panel.update(state, *loaded, **renderer, 96, 54, /*shown=*/true, /*wait=*/true);
    const ScalingResult* r = panel.measured();
    ASSERT_NE(r, nullptr);
    ASSERT_EQ(r->points.size(), 3u);  // 1, 2 and 4 copies
    EXPECT_EQ(r->width, 96);
    for (const ScalingPoint& p : r->points) {
        ASSERT_TRUE(p.gl_raster_ms.has_value()) << "OpenGL's frames are drawn while the panel waits";
        EXPECT_GT(*p.gl_raster_ms, 0);
        EXPECT_EQ(p.cast_ms.size(), 2u);
    }
}

/// The ray a preset steps, recorded through its structure as the window's stepper
/// records it, and the event its step shows (the last one when the step is past the end).
struct PresetRay {
    Mesh mesh;        ///< the preset's scene
    NodeBoxes boxes;  ///< its structure's node boxes
    SteppedRay trace;
    TraversalEvent shown;
    std::optional<SlabInspection> slabs;  ///< the slab inspector's figures, when `shown` is a box test
    /// The slabs' own intersection, before the ray's [t_min, t_max] clamps it.
    float slabs_enter() const { return std::max({slabs->axis_min[0], slabs->axis_min[1], slabs->axis_min[2]}); }
    float slabs_exit() const { return std::min({slabs->axis_max[0], slabs->axis_max[1], slabs->axis_max[2]}); }
    size_t count(EventKind kind) const {
        return size_t(std::count_if(trace.events.begin(), trace.events.end(),
                                    [&](const TraversalEvent& e) { return e.kind == kind; }));
    }
};

PresetRay preset_ray(const std::string& name) {
    PresetRay out;
    auto state = load_app_state_file(kPresetDir + "/" + name + ".json");
    EXPECT_TRUE(state) << state.error();
    if (!state) return out;
    EXPECT_TRUE(state->stepper.open && state->stepper.ray) << name << " steps no ray";
    if (!state->stepper.ray) return out;
    auto mesh = load_scene(state->scene);
    EXPECT_TRUE(mesh) << mesh.error();
    if (!mesh) return out;
    auto accel = build_accelerator(*mesh, state->accel);
    EXPECT_TRUE(accel) << accel.error();
    if (!accel) return out;
    out.mesh = std::move(*mesh);
    out.boxes = NodeBoxes(**accel);
    out.trace = record_ray(**accel, *state->stepper.ray, state->stepper.any_hit ? StopAt::AnyHit : StopAt::ClosestHit);
    const size_t step = std::min(state->stepper.step, out.trace.events.size());
    EXPECT_GT(step, 0u) << name;
    if (step > 0) out.shown = out.trace.events[step - 1];
    if (out.shown.kind == EventKind::BoxTest) {
        out.slabs = inspect_box_test(out.trace, out.boxes, out.shown);
        EXPECT_TRUE(out.slabs && out.slabs->agrees) << name << ": the inspector disagrees with the traversal";
    }
    return out;
}

TEST(Presets, RayTrianglePresetsShowAHitAndEachWayToMiss) {
    // Step 1: the one triangle's test (naive structure), the triangle inspector's subject.
    auto both_ways = [](const PresetRay& r) { return plane_first_test(r.mesh.triangle(r.shown.tri), r.trace.ray); };
    const PresetRay hit = preset_ray("02-ray-triangle-hit");
    ASSERT_EQ(hit.shown.kind, EventKind::TriangleTest);
    EXPECT_TRUE(hit.shown.hit);
    EXPECT_TRUE(both_ways(hit).hit);
    EXPECT_NEAR(both_ways(hit).t, hit.shown.t, 1e-5f);

    const PresetRay u_negative = preset_ray("03-ray-triangle-u-negative");
    ASSERT_EQ(u_negative.shown.kind, EventKind::TriangleTest);
    EXPECT_FALSE(u_negative.shown.hit);
    EXPECT_LT(u_negative.shown.u, 0.0f);
    EXPECT_GE(u_negative.shown.v, 0.0f);
    EXPECT_GE(1.0f - u_negative.shown.u - u_negative.shown.v, 0.0f) << "u alone is negative";
    EXPECT_LT(both_ways(u_negative).edge[2], 0.0f) << "the edge p2-p0 fails";

    const PresetRay beyond = preset_ray("04-ray-triangle-u-plus-v-over-1");
    ASSERT_EQ(beyond.shown.kind, EventKind::TriangleTest);
    EXPECT_FALSE(beyond.shown.hit);
    EXPECT_GE(beyond.shown.u, 0.0f);
    EXPECT_GE(beyond.shown.v, 0.0f);
    EXPECT_GT(beyond.shown.u + beyond.shown.v, 1.0f);
    EXPECT_LT(both_ways(beyond).edge[1], 0.0f) << "the edge p1-p2 fails";

    const PresetRay parallel = preset_ray("05-ray-triangle-parallel");
    ASSERT_EQ(parallel.shown.kind, EventKind::TriangleTest);
    EXPECT_FALSE(parallel.shown.hit);
    EXPECT_TRUE(both_ways(parallel).parallel);
}

TEST(Presets, SlabPresetsShowEachCaseOfTheSlabTest) {
    // Each stops at the root's box test (step 1), the slab inspector's subject:
    // t_enter = max of the slabs' entries, t_exit = min of their exits.
    const PresetRay hit = preset_ray("08-slab-hit");
    ASSERT_EQ(hit.shown.kind, EventKind::BoxTest);
    ASSERT_TRUE(hit.slabs);
    EXPECT_TRUE(hit.shown.hit);
    EXPECT_LT(hit.slabs_enter(), hit.slabs_exit());
    EXPECT_GT(hit.slabs_enter(), 0.0f);

    const PresetRay miss = preset_ray("09-slab-miss");
    ASSERT_EQ(miss.shown.kind, EventKind::BoxTest);
    ASSERT_TRUE(miss.slabs);
    EXPECT_FALSE(miss.shown.hit);
    // The slide's case: t_min^y < t_max^y < t_min^x < t_max^x.
    EXPECT_LT(miss.slabs->axis_min[1], miss.slabs->axis_max[1]);
    EXPECT_LT(miss.slabs->axis_max[1], miss.slabs->axis_min[0]);
    EXPECT_LT(miss.slabs->axis_min[0], miss.slabs->axis_max[0]);
    EXPECT_GT(miss.slabs_exit(), 0.0f) << "in front of the ray: not the box-behind case";

    const PresetRay behind = preset_ray("10-slab-box-behind");
    ASSERT_EQ(behind.shown.kind, EventKind::BoxTest);
    ASSERT_TRUE(behind.slabs);
    EXPECT_FALSE(behind.shown.hit);
    EXPECT_LT(behind.slabs_enter(), behind.slabs_exit()) << "the slabs overlap";
    EXPECT_LT(behind.slabs_exit(), 0.0f) << "but behind the origin";

    const PresetRay inside = preset_ray("11-slab-origin-inside");
    ASSERT_EQ(inside.shown.kind, EventKind::BoxTest);
    ASSERT_TRUE(inside.slabs);
    EXPECT_TRUE(inside.shown.hit);
    EXPECT_LT(inside.slabs_enter(), 0.0f);
    EXPECT_GT(inside.slabs_exit(), 0.0f);

    const PresetRay parallel = preset_ray("12-slab-parallel");
    ASSERT_EQ(parallel.shown.kind, EventKind::BoxTest);
    ASSERT_TRUE(parallel.slabs);
    EXPECT_EQ(parallel.trace.ray.dir.y, 0.0f) << "parallel to the y slab";
    EXPECT_EQ(parallel.slabs->axis_min[1], -kInfinity);
    EXPECT_EQ(parallel.slabs->axis_max[1], kInfinity);
    EXPECT_TRUE(parallel.shown.hit);
}

TEST(Presets, OneBoxCostsOneTestOnAMissAndEveryTriangleOnAHit) {
    const PresetRay miss = preset_ray("13-bounding-box-miss");
    ASSERT_EQ(miss.shown.kind, EventKind::Done);
    EXPECT_FALSE(miss.shown.hit);
    EXPECT_EQ(miss.count(EventKind::BoxTest), 1u);
    EXPECT_EQ(miss.count(EventKind::TriangleTest), 0u);

    const PresetRay hit = preset_ray("14-bounding-box-hit");
    ASSERT_EQ(hit.shown.kind, EventKind::Done);
    EXPECT_TRUE(hit.shown.hit);
    EXPECT_EQ(hit.count(EventKind::BoxTest), 1u) << "one box: the whole scene in one leaf";
    EXPECT_EQ(hit.count(EventKind::TriangleTest), hit.mesh.triangle_count()) << "and every triangle tested";
}

TEST(Presets, OverlappingSiblingsAreBothEntered) {
    // The root's two children: their boxes overlap, the ray tests both, enters the
    // nearer (2) first and finds nothing, then the other (1), where its hit is.
    const PresetRay r = preset_ray("19-bvh-overlapping-siblings");
    ASSERT_EQ(r.shown.kind, EventKind::VisitNode);
    EXPECT_EQ(r.shown.node, 1u);
    EXPECT_FALSE(intersection(*r.boxes.node(1), *r.boxes.node(2)).empty()) << "the sibling boxes overlap";
    std::vector<uint32_t> visits;
    size_t second_visit = 0, first_hit = 0;  // event numbers
    for (size_t i = 0; i < r.trace.events.size(); ++i) {
        const TraversalEvent& e = r.trace.events[i];
        if (e.kind == EventKind::VisitNode && (e.node == 1 || e.node == 2)) {
            visits.push_back(e.node);
            if (visits.size() == 2) second_visit = i + 1;
        }
        if (e.kind == EventKind::NewClosest && first_hit == 0) first_hit = i + 1;
    }
    EXPECT_EQ(visits, (std::vector<uint32_t>{2, 1})) << "the nearer sibling first, then the other";
    EXPECT_GT(first_hit, second_visit) << "the hit is found in the second sibling";
    EXPECT_TRUE(r.trace.hit.found());
}

TEST(Presets, AlgorithmTwoFindsTheSameHitWithLessWork) {
    const PresetRay one = preset_ray("22-bvh-algorithm-1");
    const PresetRay two = preset_ray("23-bvh-algorithm-2");
    ASSERT_EQ(one.shown.kind, EventKind::Done);
    ASSERT_EQ(two.shown.kind, EventKind::Done);
    ASSERT_TRUE(one.shown.hit);
    EXPECT_EQ(one.trace.ray.origin, two.trace.ray.origin) << "the same ray";
    EXPECT_EQ(one.trace.ray.dir, two.trace.ray.dir);
    EXPECT_EQ(one.trace.hit.tri, two.trace.hit.tri);
    EXPECT_EQ(one.trace.hit.t, two.trace.hit.t);
    EXPECT_LT(two.count(EventKind::BoxTest), one.count(EventKind::BoxTest));
    EXPECT_LT(two.count(EventKind::TriangleTest), one.count(EventKind::TriangleTest));
    EXPECT_GT(two.count(EventKind::Cull), 0u) << "early termination culls boxes beyond the closest hit";
}

TEST(Presets, RaySteppingPresetsStopWhereTheirCaptionsSay) {
    const PresetRay watertight = preset_ray("06-watertight-triangle-test");
    ASSERT_EQ(watertight.shown.kind, EventKind::Done);
    EXPECT_FALSE(watertight.shown.hit) << "Moller-Trumbore lets the ray from inside slip out";

    const PresetRay walk = preset_ray("29-grid-cell-walk");
    EXPECT_EQ(walk.shown.kind, EventKind::EnterCell);
    EXPECT_GE(walk.count(EventKind::EnterCell), 3u) << "a walk through several cells";
    EXPECT_TRUE(walk.trace.hit.found()) << "and it ends on a hit";
}

TEST(Presets, AxisAlignedBoxesCountEveryBoxTestOfTheRayBothWays) {
    const PresetRay ray = preset_ray("07-why-axis-aligned-boxes");
    ASSERT_EQ(ray.shown.kind, EventKind::Done) << "the whole ray: every box test counted";
    const uint64_t box_tests = ray.count(EventKind::BoxTest);
    EXPECT_GE(box_tests, 3u);
    const BoxTestOps axis = box_test_ops(box_tests, kAxisPlaneOps);
    const BoxTestOps general = box_test_ops(box_tests, kGeneralPlaneOps);
    EXPECT_EQ(axis.divides, int64_t(6 * box_tests));
    EXPECT_EQ(axis.multiplies, 0);
    EXPECT_EQ(general.multiplies, int64_t(36 * box_tests));
}

TEST(Presets, ConstructionPresetsShowASplitThenAChildsSplitThenALeaf) {
    // The decision each preset opens at, from the build the construction stepper records.
    auto decision = [](const std::string& name) {
        auto state = load_app_state_file(kPresetDir + "/" + name + ".json");
        EXPECT_TRUE(state) << state.error();
        EXPECT_TRUE(state->build_step.active) << name;
        auto loaded = load_and_build(state->scene, state->accel);
        EXPECT_TRUE(loaded) << loaded.error();
        std::shared_ptr<const BuildTrace> trace = record_build(*loaded);
        EXPECT_TRUE(trace && size_t(state->build_step.step) < trace->steps.size()) << name;
        return std::make_pair(trace, trace->steps[size_t(state->build_step.step)]);
    };
    const auto [root_trace, root] = decision("16-bvh-construction");
    EXPECT_EQ(root.depth, 0u);
    EXPECT_GT(root.left_count, 0u);
    const auto [child_trace, child] = decision("17-bvh-construction-recurse");
    EXPECT_EQ(child.depth, 1u);
    ASSERT_GT(child.left_count, 0u) << "a split";
    // The panel's S_A/S_N and S_B/S_N, put into the lecture's formula, give the split's cost.
    const Bvh& bvh = child_trace->bvh;
    const BvhNode& node = bvh.nodes[child.node];
    const float area = node.bounds.area();
    const float p_a = bvh.nodes[node.first].bounds.area() / area, p_b = bvh.nodes[node.first + 1].bounds.area() / area;
    EXPECT_GT(p_a, 0.0f);
    EXPECT_LE(p_a, 1.0f);
    EXPECT_LE(p_b, 1.0f);
    EXPECT_NEAR(1.0f + p_a * float(child.left_count) + p_b * float(child.count - child.left_count), child.split_cost,
                1e-4f * child.split_cost);
    const auto [leaf_trace, leaf] = decision("18-bvh-construction-leaf");
    EXPECT_TRUE(leaf_trace->bvh.nodes[leaf.node].is_leaf());
    EXPECT_EQ(leaf.decision, BuildDecision::LeafFits);
    EXPECT_LE(leaf.count, 5u);
    EXPECT_GT(leaf.count, 0u);
}

TEST(Presets, TheKdPlanePresetShowsTheRootsPlaneAsTheCheapestWithStraddlers) {
    // Its caption: the SAH weighs every side of the boxes and the tree's plane is the
    // cheapest, a plane cutting off empty space costs less, a triangle crossing the
    // plane goes to both sides.
    auto state = load_app_state_file(kPresetDir + "/31-kd-planes.json");
    ASSERT_TRUE(state) << state.error();
    EXPECT_TRUE(state->build_step.active);
    auto loaded = load_and_build(state->scene, state->accel);
    ASSERT_TRUE(loaded) << loaded.error();
    const KdTree* kd = structure_if<KdTree>(*(*loaded)->accel);
    ASSERT_NE(kd, nullptr);
    const uint32_t node = uint32_t(state->build_step.step);
    ASSERT_FALSE(kd->nodes[node].is_leaf());
    const KdSahChart chart = kd_sah_chart(*(*loaded)->mesh, *kd, node, kd->build_config);
    EXPECT_EQ(chart.best_axis, kd->nodes[node].axis());
    EXPECT_EQ(chart.best_position, kd->nodes[node].split());
    EXPECT_LT(chart.best_cost, chart.leaf_cost);
    EXPECT_GT(chart.best_below + chart.best_above, chart.count) << "triangles crossing the plane, on both sides";
    EXPECT_GT(kd->build_config.empty_bonus, 0.0f);
}

TEST(Presets, TheKdChallengeIsWrongWithoutTheInCellRuleAndRightWithIt) {
    // builtin:kd-challenge: triangle 0 is b (hit first, in the first cell's walk, but
    // beyond that cell), 1 is a (nearer, in the second cell only).
    const PresetRay naive_rule = preset_ray("32-kd-in-cell-rule-off");
    ASSERT_EQ(naive_rule.shown.kind, EventKind::Done);
    EXPECT_EQ(naive_rule.trace.hit.tri, 0u) << "the naive rule answers b";
    EXPECT_EQ(naive_rule.count(EventKind::HitOutsideCell), 0u);

    const PresetRay in_cell = preset_ray("33-kd-in-cell-rule-on");
    EXPECT_EQ(in_cell.shown.kind, EventKind::HitOutsideCell) << "b's hit lies beyond the cell it was found in";
    EXPECT_EQ(in_cell.shown.tri, 0u);
    EXPECT_EQ(in_cell.trace.hit.tri, 1u) << "a, the nearer one";
    EXPECT_EQ(in_cell.trace.ray.origin, naive_rule.trace.ray.origin) << "the same ray";
    EXPECT_EQ(in_cell.trace.ray.dir, naive_rule.trace.ray.dir);
}

TEST(Presets, TheShadowRayStopsAtItsFirstHitAndTheReflectionRayFindsTheNearest) {
    // builtin:cornell-mirror: triangles 12..21 are the short block, 22..31 the mirror block.
    const PresetRay shadow = preset_ray("41-shadow-ray-any-hit");
    EXPECT_EQ(shadow.trace.query, StopAt::AnyHit);
    ASSERT_EQ(shadow.shown.kind, EventKind::TriangleTest) << "the step shown is the hit that ends the walk";
    EXPECT_TRUE(shadow.shown.hit);
    EXPECT_EQ(shadow.shown.tri, 17u) << "the short block's side";
    EXPECT_EQ(shadow.trace.events.back().kind, EventKind::Done) << "and the next event ends it";
    EXPECT_EQ(shadow.trace.events.size(), 29u);
    EXPECT_EQ(shadow.trace.ray.t_max, 1.0f) << "from the floor to the light";
    EXPECT_EQ(shadow.count(EventKind::NewClosest), 0u) << "any-hit keeps no nearest hit";

    const PresetRay reflection = preset_ray("42-reflection-ray");
    EXPECT_EQ(reflection.trace.query, StopAt::ClosestHit);
    ASSERT_EQ(reflection.shown.kind, EventKind::Done);
    EXPECT_EQ(reflection.trace.hit.tri, 19u) << "the short block's back, which the camera cannot see";
    // The ray starts on the mirror (the front of the tall block, triangle 24's plane), a hair in front.
    const Triangle mirror = reflection.mesh.triangle(24);
    const Vec3 n = normalize(cross(mirror.edge1, mirror.edge2));
    const float off_plane = std::fabs(dot(reflection.trace.ray.origin - mirror.p0, n));
    EXPECT_GT(off_plane, 0.0f);
    EXPECT_LT(off_plane, 1e-4f);
    EXPECT_EQ(reflection.mesh.mirror.at(24), 1);
}

TEST(Presets, TheRefitPresetShowsAnEarlierTreeRefittedAndCostlierThanARebuild) {
    auto state = load_app_state_file(kPresetDir + "/45-refit-against-rebuild.json");
    ASSERT_TRUE(state) << state.error();
    ASSERT_TRUE(state->refit_bvh);
    auto refitted = load_and_build_or_refit(state->scene, state->accel, true);
    auto rebuilt = load_and_build(state->scene, state->accel);
    ASSERT_TRUE(refitted) << refitted.error();
    ASSERT_TRUE(rebuilt) << rebuilt.error();
    EXPECT_TRUE((*refitted)->refitted);
    EXPECT_FALSE((*rebuilt)->refitted);
    EXPECT_EQ((*refitted)->mesh->positions, (*rebuilt)->mesh->positions) << "the same time of the scene";
    const double refit_cost = structure_if<Bvh>(*(*refitted)->accel)->build_stats.sah_cost;
    const double rebuild_cost = structure_if<Bvh>(*(*rebuilt)->accel)->build_stats.sah_cost;
    EXPECT_GT(refit_cost, 1.25 * rebuild_cost) << "the caption says a third above";
}

TEST(Presets, TheRefitPresetLoadedInTheWindowShowsTheRefittedTree) {
    // As PageDown or the preset list loads it (Session::apply_state), not only at start-up.
    Session session;
    AppState state;
    auto preset = load_app_state_file(kPresetDir + "/45-refit-against-rebuild.json");
    ASSERT_TRUE(preset) << preset.error();
    session.apply_state(state, *preset);
    wait_for_loader(session);
    session.take_finished_load(state);
    ASSERT_NE(session.scene, nullptr);
    EXPECT_EQ(session.scene->source, preset->scene);
    EXPECT_TRUE(session.scene->refitted);
}

TEST(Presets, TheSliceViewTurnedOffWhileComputingGoesIdle) {
    auto loaded = load_and_build("builtin:sphere?subdiv=3", AccelConfig{});
    ASSERT_TRUE(loaded) << loaded.error();
    SliceView slice;
    AppState state;
    state.view.slice = true;
    slice.update(state, *loaded, /*wait=*/false);  // asked for, not waited for
    state.view.slice = false;
    const auto start = std::chrono::steady_clock::now();
    while (slice.busy() && std::chrono::steady_clock::now() - start < std::chrono::seconds(10)) {
        slice.update(state, *loaded, false);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    EXPECT_FALSE(slice.busy()) << "a slice nobody wants any more must not count as pending work";
}

TEST(Presets, TheNearestPointSearchSkipsABoxOutsideTheSphere) {
    auto state = load_app_state_file(kPresetDir + "/43-nearest-point.json");
    ASSERT_TRUE(state) << state.error();
    ASSERT_TRUE(state->nearest.open && state->nearest.point);
    auto mesh = load_scene(state->scene);
    ASSERT_TRUE(mesh) << mesh.error();
    auto accel = build_accelerator(*mesh, state->accel);
    ASSERT_TRUE(accel) << accel.error();
    auto search = record_nearest(**accel, *mesh, *state->nearest.point);
    ASSERT_TRUE(search) << search.error();
    const size_t step = state->nearest.step;
    ASSERT_GT(step, 0u);
    ASSERT_LE(step, search->events.size());
    const TraversalEvent& shown = search->events[step - 1];
    const StepState before = replay(search->events, step);
    // The step shown: a box skipped because it lies wholly outside the sphere of the
    // best distance, found earlier, which is already the final answer's.
    ASSERT_EQ(shown.kind, EventKind::Cull);
    ASSERT_TRUE(before.closest.found());
    EXPECT_GT(shown.t_enter, before.closest.t);
    EXPECT_EQ(before.closest.tri, search->result.tri);
    const NearestPoint brute = [&] { NoObserver none; return nearest_point_brute_force(*mesh, *state->nearest.point, none); }();
    EXPECT_EQ(search->result.tri, brute.tri);
    EXPECT_EQ(search->result.distance_squared, brute.distance_squared);
}

}  // namespace
}  // namespace accelviz
