// `accelviz bench-view SCENE [--frames N] [structure, overlay and camera flags] [--json]`:
// how fast the window draws. The window's own frame code (draw_frame, through
// OSMesa, as `render --view gui|structure` uses it) draws N frames while the camera
// orbits the scene once around its target, as a lecturer turning it would; each
// frame is timed to glFinish. Prints the median, 90th percentile and worst frame,
// the first frame (the overlay's upload, and the mesh's when rasterized) apart, and
// the process's peak memory.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <thread>

#include <nlohmann/json.hpp>

#include "app/cli/accel_flags.h"
#include "app/cli/camera_flags.h"
#include "app/cli/commands.h"
#include "app/cli/flag_checks.h"
#include "app/cli/preset_flag.h"
#include "app/cli/progress.h"
#include "app/cli/scene_input.h"
#include "app/cli/window_flags.h"
#include "app/gui/camera_control.h"
#include "app/gui/headless.h"
#include "app/gui/moving_box_budget.h"
#include "app/gui/scene_loader.h"
#include "app/gui/session.h"
#include "core/accel/memory_budget.h"

namespace accelviz::cli {
namespace {

/// Frames of the still view timed after the orbit (the window draws three after an event).
constexpr int kRedrawFrames = 5;

struct BenchViewOptions {
    std::string scene;
    PresetFlag preset;
    int frames = 60;
    int width = 1280, height = 720;
    std::string view = "gui";
    std::string overlay;  ///< "on" | "off" | "" (the preset's or the window's default)
    int max_boxes = -1;   ///< -1: the preset's or the window's default
    std::string draw;     ///< "raster" | "raycast" | "auto" | "" (the preset's, else auto)
    bool json = false;
    CameraFlags camera;
    AccelConfig accel;
};

int fail(const std::string& message) {
    std::cerr << "accelviz bench-view: " << message << "\n";
    return 1;
}

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// The q-quantile (0..1) of `values` by the nearest rank.
double quantile(std::vector<double> values, double q) {
    std::sort(values.begin(), values.end());
    const size_t rank = size_t(std::ceil(q * double(values.size())));
    return values[std::clamp<size_t>(rank, 1, values.size()) - 1];
}

/// Peak resident memory of the process so far, in bytes.
uint64_t peak_memory_bytes() {
    rusage usage{};
    getrusage(RUSAGE_SELF, &usage);
    return uint64_t(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

int run_bench_view(const BenchViewOptions& opt) {
    if (!opt.preset.error.empty()) return fail("--preset: " + opt.preset.error);
    if (auto err = validate(opt.accel)) return fail(err->message);
    AppState state = opt.preset.state.value_or(AppState{});
    if (!opt.scene.empty()) state.scene = opt.scene;
    else if (!opt.preset.state) return fail("no scene: give SCENE (an OBJ file or builtin:NAME) or --preset FILE");
    state.accel = opt.accel;
    if (!opt.overlay.empty()) state.overlay.show_structure = opt.overlay == "on";
    if (opt.max_boxes >= 0) state.overlay.max_boxes = size_t(opt.max_boxes);
    apply_draw_flag(opt.draw, state);
    const WindowView view = *kWindowViewNames.parse(opt.view);  // CLI11 checked the name

    const auto start = std::chrono::steady_clock::now();
    LoadResult loaded = [&] {
        const StepProgress progress("bench-view", "loading and building");
        return load_and_build_or_refit(state.scene, state.accel, state.refit_bvh);
    }();
    if (!loaded) return fail(loaded.error());
    const double load_and_build_ms = ms_since(start);
    print_scene_note((*loaded)->degenerate_note, state.scene, "bench-view");
    print_memory_budget_note(*(*loaded)->accel, "bench-view");
    auto params = state.camera ? opt.camera.resolve(*state.camera) : opt.camera.resolve((*loaded)->bounds);
    if (!params) return fail(params.error());
    state.camera = *params;
    const bool framed_by_window = !opt.camera.any() && !opt.preset.state;  // as the window frames a new scene

    auto app = HeadlessApp::create(opt.width, opt.height);
    if (!app) return fail(app.error());
    Session& session = (*app)->session();
    (*app)->renderer().prepare_frame_copies();  // as the window does at its start
    const size_t triangles = (*loaded)->mesh->triangle_count();
    session.set_scene(state, std::move(*loaded), !framed_by_window);
    FrameInput input;
    input.draw_ui = view != WindowView::Structure;
    input.wait_for_ray_cast = true;  // a ray-cast mesh is part of its frame (a quarter of the pixels while orbiting)

    // The first frame uploads the overlay (and the mesh, when it is rasterized); later
    // ones only draw. The orbit: one turn about the target in `frames` steps (yaw only:
    // the camera never rolls).
    auto timed_frame = [&] {
        const auto frame_start = std::chrono::steady_clock::now();
        (*app)->draw(state, input);
        input.frame_ms = ms_since(frame_start);  // as the window tells the next frame
        return input.frame_ms;
    };
    const double first_ms = timed_frame();
    std::vector<double> frame_ms;
    frame_ms.reserve(size_t(opt.frames));
    int ray_cast_frames = 0;  // frames whose mesh the CPU ray caster drew
    // The boxes orbit frames draw follow their time (MovingBoxBudget): the fewest and most.
    size_t fewest_moving_boxes = SIZE_MAX, most_moving_boxes = 0, last_moving_boxes = 0;
    std::vector<size_t> moving_boxes;  // each orbit frame's
    auto shown = [&](size_t moving) { return state.overlay.show_structure ? moving : 0; };
    for (int i = 0; i < opt.frames; ++i) {
        orbit(*state.camera, 2.0 * std::numbers::pi / opt.frames, 0.0);
        frame_ms.push_back(timed_frame());
        ray_cast_frames += session.mesh_ray_cast ? 1 : 0;
        last_moving_boxes = session.overlay.moving_prefix(session.moving_boxes.boxes());  // this frame's
        moving_boxes.push_back(shown(last_moving_boxes));
        fewest_moving_boxes = std::min(fewest_moving_boxes, last_moving_boxes);
        most_moving_boxes = std::max(most_moving_boxes, last_moving_boxes);
    }
    // The camera stopped: the full picture (ray cast: every pixel, after the still time).
    std::this_thread::sleep_for(std::chrono::duration<double>(Session::kCameraStillSeconds));
    const double still_ms = timed_frame();
    // A still view too slow for one frame draws its boxes a share per frame: the frames
    // after the first, until all are in.
    int more_frames = 0;
    double worst_more_ms = 0;
    while (session.view_cache.drawing_on()) {
        worst_more_ms = std::max(worst_more_ms, timed_frame());
        ++more_frames;
    }
    // The window then draws a few frames after every event (a mouse move over a panel)
    // with the view unchanged: those frames.
    std::vector<double> redraw_ms;
    for (int i = 0; i < kRedrawFrames; ++i) redraw_ms.push_back(timed_frame());
    const double redraw = quantile(redraw_ms, 0.5);
    const double median = quantile(frame_ms, 0.5), p90 = quantile(frame_ms, 0.9),
                 worst = *std::max_element(frame_ms.begin(), frame_ms.end());
    const size_t boxes = session.overlay.boxes.size();
    const uint64_t peak = peak_memory_bytes();

    if (opt.json) {
        nlohmann::json out = {{"scene", state.scene},
                              {"triangles", triangles},
                              {"structure", std::string(to_string(state.accel.type))},
                              {"view", opt.view},
                              {"width", opt.width},
                              {"height", opt.height},
                              {"frames", opt.frames},
                              {"overlay", state.overlay.show_structure},
                              {"overlay_boxes", boxes},
                              {"overlay_boxes_while_moving", shown(last_moving_boxes)},
                              {"overlay_boxes_while_moving_fewest", shown(fewest_moving_boxes)},
                              {"overlay_boxes_while_moving_most", shown(most_moving_boxes)},
                              {"draw", std::string(to_string(state.view.draw_with))},
                              {"ray_cast_frames", ray_cast_frames},
                              {"still_frame_ms", still_ms},
                              {"still_more_frames", more_frames},
                              {"still_more_worst_ms", worst_more_ms},
                              {"still_redraw_ms", redraw},
                              {"load_and_build_ms", load_and_build_ms},
                              {"first_frame_ms", first_ms},
                              {"median_frame_ms", median},
                              {"p90_frame_ms", p90},
                              {"worst_frame_ms", worst},
                              {"frame_ms_runs", frame_ms},
                              {"overlay_boxes_while_moving_runs", moving_boxes},
                              {"frames_per_s", median > 0 ? 1000.0 / median : 0.0},
                              {"peak_memory_bytes", peak},
                              {"gl", (*app)->gl_description()}};
        std::cout << out.dump(2) << "\n";
        return 0;
    }
    std::printf("scene      %s (%zu triangles), %s, %s view %dx%d, overlay %s (%zu boxes)\n", state.scene.c_str(),
                triangles, std::string(to_string(state.accel.type)).c_str(), opt.view.c_str(), opt.width, opt.height,
                state.overlay.show_structure ? "on" : "off", boxes);
    std::printf("load+build %.1f ms\n", load_and_build_ms);
    std::printf("frames     %d while orbiting once: median %.1f ms (%.1f frames/s), 90%% %.1f ms, worst %.1f ms\n",
                opt.frames, median, median > 0 ? 1000.0 / median : 0.0, p90, worst);
    if (state.overlay.show_structure && boxes > 0)
        std::printf("boxes      %zu while moving at the end (%zu to %zu: the budget follows the frame time)\n",
                    last_moving_boxes, fewest_moving_boxes, most_moving_boxes);
    std::printf("draw with  %s: the mesh ray cast by the CPU in %d of %d frames\n",
                std::string(to_string(state.view.draw_with)).c_str(), ray_cast_frames, opt.frames);
    std::printf("still      %.1f ms (the camera stopped: a ray-cast mesh gets every pixel)\n", still_ms);
    if (more_frames > 0)
        std::printf("           then %d more frames (worst %.1f ms) to draw every box, a share per frame\n",
                    more_frames, worst_more_ms);
    std::printf("redraw     %.1f ms (median of %d frames of the still view, as after a mouse move over a panel)\n",
                redraw, kRedrawFrames);
    std::printf("first      %.1f ms (uploads the overlay, and the mesh when rasterized)\n", first_ms);
    std::printf("peak mem   %s\n", format_bytes(peak).c_str());
    std::printf("gl         %s\n", (*app)->gl_description().c_str());
    return 0;
}

}  // namespace

Command register_bench_view(CLI::App& app) {
    auto opt = std::make_shared<BenchViewOptions>();
    CLI::App* sub = app.add_subcommand(
        "bench-view", "Time the window's 3D view: draw frames headlessly (OSMesa, the window's own code) while the "
                      "camera orbits the scene once; print median, 90th-percentile and worst frame times and peak memory");
    sub->add_option("scene", opt->scene, "OBJ file, or builtin:NAME; optional with --preset");
    add_preset_flag(*sub, opt->preset, opt->accel,
                    "Start from this saved window state (a JSON file, or a shipped preset's name): its scene, "
                    "structure, camera, overlay and view. SCENE and the flags given replace its values");
    sub->add_option("--frames", opt->frames, "Frames timed while the camera turns once around its target")
        ->check(whole_number(2, 100000))
        ->capture_default_str();
    sub->add_option("--width", opt->width, "Frame width in pixels")->check(whole_number(16, 8192))->capture_default_str();
    sub->add_option("--height", opt->height, "Frame height in pixels")
        ->check(whole_number(16, 8192))
        ->capture_default_str();
    sub->add_option("--view", opt->view,
                    "gui (the whole window, panels included) | structure (the 3D view alone)")
        ->check(CLI::IsMember(std::vector<std::string>{"gui", "structure"}))
        ->capture_default_str();
    sub->add_option("--overlay", opt->overlay,
                    "on | off: draw the structure's boxes, cells or planes (default: on, or the preset's)")
        ->check(CLI::IsMember(std::vector<std::string>{"on", "off"}));
    sub->add_option("--max-boxes", opt->max_boxes,
                    "The overlay's box budget: deeper levels are left out beyond it (0 = no limit; default "
                    "200000, or the preset's)")
        ->check(whole_number(0, INT32_MAX, ">= 0"));
    add_draw_flag(*sub, opt->draw,
                  "whichever is measured faster; orbit frames draw a quarter of the pixels and the overlay's "
                  "shallow levels only (" + std::to_string(MovingBoxBudget::kStartBoxes) +
                      " boxes at first, then as many as keep a frame under " +
                      std::to_string(int(MovingBoxBudget::kTargetMs)) +
                      " ms), the still frame after every pixel and box");
    sub->add_flag("--json", opt->json, "Print one JSON object instead of the table");
    opt->camera.add_to(*sub);
    add_accel_flags(*sub, opt->accel);
    return {sub, [opt] { return run_bench_view(*opt); }};
}

}  // namespace accelviz::cli
