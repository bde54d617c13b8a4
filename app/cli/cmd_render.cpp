// `accelviz render [SCENE] --out FILE.png [--preset FILE]`: the CPU views, and
// the window's own views (structure, gui) through OSMesa, rendered headless.
//
// What is rendered is an AppState: the preset's (--preset), or the defaults,
// with the command line's scene, structure flags and camera flags laid over it
// where they were given.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "app/cli/accel_flags.h"
#include "app/cli/camera_flags.h"
#include "app/cli/commands.h"
#include "app/cli/progress.h"
#include "app/cli/flag_checks.h"
#include "app/cli/light_flags.h"
#include "app/cli/preset_flag.h"
#include "app/cli/scene_input.h"
#include "app/cli/window_flags.h"
#include "app/gui/app_state.h"
#include "app/gui/headless.h"
#include "app/gui/presets.h"
#include "app/gui/stepper_panel.h"
#include "app/gui/scene_loader.h"
#include "core/geometry/scene.h"
#include "app/gl/gpu_ray_caster.h"
#include "app/gl/raster_timer.h"
#include "app/gl/renderer.h"
#include "app/platform/osmesa_context.h"
#include "core/measure/scaling.h"
#include "core/render/chart.h"
#include "core/query/inside_slice.h"
#include "core/render/ray_caster.h"
#include "core/render/views.h"
#include "core/util/enum_names.h"

namespace accelviz::cli {
namespace {

/// The structure's name, for messages and titles.
std::string accel_name(const AppState& state) { return std::string(to_string(state.accel.type)); }


struct RenderOptions {
    std::string scene;
    PresetFlag preset;               ///< --preset, read while parsing (before the structure flags apply)
    std::string out;
    std::string view = "split";  ///< --view as given; parsed once, in run_render
    std::string depth_out;
    int width = 1280, height = 720;
    int threads = 0;
    double heat_max = 0;
    CameraFlags camera;
    AccelConfig accel;
    int step = -1;              ///< build-step: the decision to show; step: events applied (-1: not given)
    std::string pixel;          ///< step: the pixel whose ray is stepped
    bool accel_given = false;   ///< --accel was on the command line
    std::optional<double> time;  ///< --time: the moving scene's t (scene_at_time)
    std::string draw;            ///< --draw: how the window's views draw the mesh ("": the preset's, else auto)
    LightFlags light;            ///< --shadows, --reflections, --light
    std::string rays = "primary";  ///< --rays: which rays' work the heat maps show
    std::string slice_axis;        ///< --slice-axis x|y|z ("": the preset's, else z)
    std::optional<float> slice_at;  ///< --slice-at: 0..1 of the box along the axis
    bool gpu = false;               ///< --gpu: the ray cast by the compute shader
    std::string scaling_accel = "bvh";  ///< --scaling-accel: the structures whose ray casts the chart plots
    double scaling_max = 10.5e6;        ///< --scaling-max: the biggest scene's triangles
};




/// The views the CPU renderers of core/render compose (the window's own views are WindowView).
enum class CpuView { RayCast, Raster, Split, DepthDiff, HeatNodes, HeatTris, Slice, HeatLoop, HeatStack, Scaling };
constexpr EnumNames<CpuView, 10> kCpuViewNames{{{{CpuView::RayCast, "raycast"},
                                                {CpuView::Raster, "raster"},
                                                {CpuView::Split, "split"},
                                                {CpuView::DepthDiff, "depth-diff"},
                                                {CpuView::HeatNodes, "heat-nodes"},
                                                {CpuView::HeatTris, "heat-tris"},
                                                {CpuView::Slice, "slice"},
                                                {CpuView::HeatLoop, "heat-loop"},
                                                {CpuView::HeatStack, "heat-stack"},
                                                {CpuView::Scaling, "scaling"}}}};

/// --view's names: the CPU views, then the window's.
std::vector<std::string> all_views() {
    std::vector<std::string> views = kCpuViewNames.names();
    for (const std::string& view : kWindowViewNames.names()) views.push_back(view);
    return views;
}

/// What the shadow rays cost as any-hit against closest-hit over the same segments.
void print_shadow_lesson(const ShadowQueryWork& w) {
    if (w.rays == 0) {
        std::fprintf(stderr, "shadow rays: none (no hit sees the light's side)\n");
        return;
    }
    const double rays = double(w.rays);
    std::fprintf(stderr,
                 "shadow rays: %llu, %.1f%% blocked; per ray, any-hit %.2f nodes and %.2f triangle tests, closest-hit on "
                 "the same segments %.2f nodes and %.2f tests\n",
                 (unsigned long long)w.rays, 100.0 * double(w.blocked) / rays, double(w.any_hit.nodes_visited) / rays,
                 double(w.any_hit.triangle_tests) / rays, double(w.closest_hit.nodes_visited) / rays,
                 double(w.closest_hit.triangle_tests) / rays);
    if (w.blocked)
        std::fprintf(stderr,
                     "  on the %llu blocked rays: any-hit %.2f nodes and %.2f tests, closest-hit %.2f nodes and %.2f "
                     "tests\n",
                     (unsigned long long)w.blocked, double(w.any_hit_blocked.nodes_visited) / double(w.blocked),
                     double(w.any_hit_blocked.triangle_tests) / double(w.blocked),
                     double(w.closest_hit_blocked.nodes_visited) / double(w.blocked),
                     double(w.closest_hit_blocked.triangle_tests) / double(w.blocked));
    if (w.disagreed)
        std::fprintf(stderr, "render: warning: any-hit and closest-hit disagree on %llu shadow rays\n",
                     (unsigned long long)w.disagreed);
}

int fail(const std::string& message) {
    std::cerr << "accelviz render: " << message << "\n";
    return 1;
}

/// The structure `state` asks for over `mesh`: built, or for a refitting moving scene
/// at a later time (refit_bvh), the t = 0 tree refitted to it, as the window shows it.
Expected<std::shared_ptr<const Accelerator>> structure_for(const AppState& state, const Mesh& mesh) {
    if (refit_start(state.scene, state.accel, state.refit_bvh)) {
        auto loaded = load_and_build_or_refit(state.scene, state.accel, true);
        if (!loaded) return Error{loaded.error()};
        return (*loaded)->accel;
    }
    return build_accelerator(mesh, state.accel);
}

/// `--gpu`: the binary BVH traversed by the compute shader (app/gl/gpu_ray_caster.h)
/// in a headless OpenGL context, beside the CPU's cast of the same rays; the view is
/// its picture (raycast), its loop iterations per pixel (heat-loop) or its stack
/// depth per pixel (heat-stack). Prints how far the two agree, and both times.
int run_render_gpu(const RenderOptions& opt, const AppState& state, CpuView view) {
    const auto mesh = load_scene_noting(state.scene, "render");
    if (!mesh) return fail(mesh.error());
    auto accel = structure_for(state, *mesh);
    if (!accel) return fail(accel.error());
    const Bvh* bvh = structure_if<Bvh>(**accel);
    if (!bvh) return fail("--gpu traverses the binary BVH: use --accel bvh (width 2)");
    if (state.accel.triangle_test != TriangleTestKind::MollerTrumbore)
        return fail("--gpu tests triangles by Moller-Trumbore: drop --triangle-test watertight");
    auto camera_params = state.camera ? opt.camera.resolve(*state.camera) : opt.camera.resolve(mesh->bounds());
    if (!camera_params) return fail(camera_params.error());
    const Camera camera(*camera_params, opt.width, opt.height);
    auto context = OsMesaContext::create(1, 1);
    if (!context) return fail(context.error());
    auto caster = GpuRayCaster::create();
    if (!caster) return fail("--gpu: " + caster.error());
    if (auto err = (*caster)->upload(*bvh)) return fail("--gpu: " + err->message);
    const GpuCast gpu = (*caster)->cast(camera);
    const auto start = std::chrono::steady_clock::now();
    const Frame cpu = ray_cast(**accel, *mesh, camera, {.threads = opt.threads});
    const double cpu_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    const GpuAgreement agree = compare_with_cpu(gpu, cpu.tri, cpu.depth);
    std::fprintf(stderr,
                 "gpu (%s): %.1f ms; cpu: %.1f ms; the same triangle on %.4f%% of %zu pixels, t within %.2g "
                 "relative\n",
                 context->get()->description().c_str(), gpu.gpu_ms, cpu_ms, 100.0 * agree.same_share(), agree.pixels,
                 agree.max_relative_t);
    Image image;
    if (view == CpuView::RayCast) image = gpu.colour;
    else if (view == CpuView::HeatLoop)
        image = heat_view(gpu.iterations, opt.width, opt.height, "GPU: loop iterations per invocation (bvh)", opt.heat_max);
    else
        image = heat_view(gpu.stack_depth, opt.width, opt.height, "GPU: deepest stack per invocation (bvh)", opt.heat_max);
    if (auto err = write_png(image, opt.out)) return fail(err->message);
    std::cout << opt.out << "\n";
    return 0;
}

/// `--view scaling`: the mesh repeated 1, 2, 4, ... times up to --scaling-max
/// triangles; per scene the frame time of OpenGL (OSMesa, the window's renderer) and
/// the CPU z-buffer rasterizing it and of ray casting it through each structure of
/// --scaling-accel, on a log-log chart (core/measure/scaling.h). The table goes to
/// stderr.
int run_render_scaling(const RenderOptions& opt, const AppState& state) {
    if (opt.camera.any())
        return fail("--view scaling frames each scene whole with its default camera: drop the camera flags");
    if (state.light.point_light() || opt.light.mirror)
        return fail("--view scaling times the headlight's picture: drop --shadows, --reflections, --light, --mirror");
    if (!state.accel.structure_file.empty())
        return fail("--view scaling builds each structure over every repeated scene: drop --structure");
    ScalingOptions options;
    options.structures.clear();
    const std::string& names = opt.scaling_accel;
    for (size_t start = 0; start <= names.size();) {
        const size_t comma = std::min(names.find(',', start), names.size());
        const std::string name = names.substr(start, comma - start);
        start = comma + 1;
        const auto type = parse_accel_type(name);
        if (name.empty()) return fail("--scaling-accel: an empty name in '" + names + "' (e.g. bvh,kd,grid)");
        if (!type || *type == AccelType::Naive) {
            std::string known;
            for (const std::string& n : kAccelTypeNames.names())
                if (n != "naive") known += (known.empty() ? "" : ", ") + n;
            return fail("--scaling-accel: '" + name + "' is not a structure to ray cast through (" + known + ")");
        }
        for (const AccelConfig& earlier : options.structures)
            if (earlier.type == *type) return fail("--scaling-accel: " + name + " is named twice");
        AccelConfig config = state.accel.type == *type ? state.accel : AccelConfig{};
        config.type = *type;
        options.structures.push_back(config);
    }
    auto mesh = load_scene_noting(state.scene, "render");
    if (!mesh) return fail(mesh.error());
    options.max_triangles = uint64_t(opt.scaling_max);
    options.width = opt.width;
    options.height = opt.height;
    options.threads = opt.threads;
    auto context = OsMesaContext::create(opt.width, opt.height);
    if (!context) return fail(context.error());
    auto renderer = Renderer::create();
    if (!renderer) return fail(renderer.error());
    RasterTimer timer(**renderer);
    options.gl_raster_ms = [&](const Mesh& m, const Camera& camera) -> Expected<double> {
        return timer.frame_ms(m, camera);
    };
    std::optional<StepProgress> step_progress;
    options.on_step = [&](const std::string& step) {
        step_progress.reset();
        step_progress.emplace("render", step);
    };
    auto result = measure_scaling(*mesh, options);
    step_progress.reset();
    if (!result) return fail(result.error());
    result->gl_renderer = context->get()->description();
    result->mesh_name = state.scene;
    Image image(opt.width, opt.height);
    draw_line_chart(image, 0, 0, opt.width, opt.height, scaling_chart(*result));
    std::fprintf(stderr, "%s", scaling_table(*result).c_str());
    if (auto err = write_png(image, opt.out)) return fail(err->message);
    std::cout << opt.out << "\n";
    return 0;
}

/// Samples along each side of `render --view slice` (3 rays per sample).
constexpr int kRenderSliceSamples = 256;

/// `--view slice`: the plane of --slice-axis / --slice-at across the scene, each
/// point inside or outside by the ray-parity vote, counted through naive or the BVH.
int run_render_slice(const RenderOptions& opt, const AppState& state) {
    const auto mesh = load_scene_noting(state.scene, "render");
    if (!mesh) return fail(mesh.error());
    auto accel = [&] {
        const StepProgress progress("render", "building " + std::string(to_string(state.accel.type)));
        return structure_for(state, *mesh);
    }();
    if (!accel) return fail(accel.error());
    if (!has_crossing_count(**accel))
        return fail("--view slice counts every crossing through naive or the binary BVH: use --accel naive or bvh");
    SliceSpec spec;
    spec.axis = opt.slice_axis.empty() ? state.view.slice_axis : opt.slice_axis[0] - 'x';
    spec.fraction = opt.slice_at.value_or(state.view.slice_at);
    spec.columns = spec.rows = kRenderSliceSamples;
    const auto start = std::chrono::steady_clock::now();
    const StepProgress progress("render", "counting crossings");
    auto slice = inside_slice(**accel, *mesh, spec);
    if (!slice) return fail(slice.error());
    std::fprintf(stderr, "slice (%s): %llu rays, %llu nodes visited, %llu triangles tested, %.1f ms\n",
                 (*accel)->name().c_str(), (unsigned long long)slice->rays, (unsigned long long)slice->nodes_visited,
                 (unsigned long long)slice->triangle_tests,
                 std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    if (auto err = write_png(slice_view(*slice, opt.width, opt.height), opt.out)) return fail(err->message);
    std::cout << opt.out << "\n";
    return 0;
}

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// A window view (structure, gui, build-step, comparison, fill-order, two-bvhs): draw_frame() through OSMesa, as the window draws it.
int run_window_view(const RenderOptions& opt, WindowView view, AppState state) {
    auto loaded = load_and_build_or_refit(state.scene, state.accel, state.refit_bvh);
    if (!loaded) return fail(loaded.error());
    print_scene_note((*loaded)->degenerate_note, state.scene, "render");
    if (opt.camera.any()) {  // over the preset's camera, or the scene's default view
        auto params = state.camera ? opt.camera.resolve(*state.camera) : opt.camera.resolve((*loaded)->bounds);
        if (!params) return fail(params.error());
        state.camera = *params;
    }
    const double build_ms = (*loaded)->build_seconds * 1e3;
    auto render = render_headless(state, std::move(*loaded), view, opt.width, opt.height);
    if (!render) return fail(render.error());
    std::fprintf(stderr, "%s view of %s (%s): build %.1f ms, frame %.1f ms (%s)\n", opt.view.c_str(),
                 state.scene.c_str(), accel_name(state).c_str(), build_ms, render->frame_ms,
                 render->gl_description.c_str());
    if (auto err = write_png(render->colour, opt.out)) return fail(err->message);
    std::cout << opt.out << "\n";
    return 0;
}

/// `--view build-step --step K`: the window's frame with the construction
/// stepper at decision K of the BVH build, or at node K of a tree from a file.
int run_build_step(const RenderOptions& opt, AppState state) {
    if (opt.step < 0) return fail("--view build-step needs --step K (the build decision to show, 0 = the root)");
    if (!state.accel.structure_file.empty()) {
        // The file's nodes in the order it numbers them (the window checks K against them).
        state.build_step.active = true;
        state.build_step.step = opt.step;
        return run_window_view(opt, WindowView::BuildStep, std::move(state));
    }
    if (!opt.preset.state && !opt.accel_given) state.accel.type = AccelType::Bvh;
    if (state.accel.type == AccelType::Kd) {
        // Our KD tree's nodes in the order its build made them.
        state.build_step.active = true;
        state.build_step.step = opt.step;
        return run_window_view(opt, WindowView::BuildStep, std::move(state));
    }
    if (state.accel.type != AccelType::Bvh)
        return fail("--view build-step steps a BVH build or a KD tree's nodes (--accel bvh|kd, not " +
                    accel_name(state) + ")");
    // The shared flags (--leaf-size, --cost-*) as the tree and the chart take them.
    if (state.accel.leaf_size) state.accel.bvh.max_leaf_size = *state.accel.leaf_size;
    if (state.accel.cost_trav) state.accel.bvh.cost_trav = *state.accel.cost_trav;
    if (state.accel.cost_isect) state.accel.bvh.cost_isect = *state.accel.cost_isect;
    state.build_step.active = true;
    state.build_step.step = opt.step;
    return run_window_view(opt, WindowView::BuildStep, std::move(state));
}

/// `--view step`: the window's frame (OSMesa) with the stepper open at step K on
/// the ray of pixel X,Y of a width x height image under the camera flags (the ray
/// `trace --pixel X,Y` prints), the 3D view looking at it from the side.
int run_render_step(const RenderOptions& opt) {
    if (opt.pixel.empty()) return fail("--view step needs --pixel X,Y (the ray to step)");
    auto picked = pixel_ray(opt.scene, opt.pixel, opt.width, opt.height, opt.camera);
    if (!picked) return fail(picked.error());
    AppState state;
    state.scene = opt.scene;
    state.accel = opt.accel;
    auto light = apply_light_flags(opt.light, state.light);
    if (!light) return fail(light.error());
    state.light = *light;
    auto mirrored = apply_mirror_flag(opt.light, state.scene);
    if (!mirrored) return fail(mirrored.error());
    state.scene = *mirrored;
    open_stepper_on(state, *picked, opt.step < 0 ? 0 : size_t(opt.step));
    auto image = render_gui_view_headless(state, WindowView::Step, opt.width, opt.height);
    if (!image) return fail(image.error());
    if (auto err = write_png(*image, opt.out)) return fail(err->message);
    std::cout << opt.out << "\n";
    return 0;
}

/// The directory a file is written into must exist: checked before any work, so a
/// typo in --out does not cost a whole render first. (Other write errors, such as
/// permissions, are reported when the file is written.)
std::string missing_directory(const std::string& path) {
    const std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (dir.empty() || std::filesystem::is_directory(dir, ec)) return {};
    return path + ": cannot write there: " + dir.string() + " is not a directory";
}

/// The structure to build (the preset's, with the flags given over it) checked before
/// any work; a bad value the preset brought is reported with the preset's file name.
std::string structure_problem(const RenderOptions& opt) {
    const auto err = validate(opt.accel);
    if (!err) return {};
    if (opt.preset.state && validate(opt.preset.state->accel)) return "--preset: " + opt.preset.path + ": structure: " + err->message;
    return err->message;
}

int run_render(const RenderOptions& given) {
    RenderOptions opt = given;
    if (opt.time) {  // the moving scene (SCENE, or the preset's) at that time
        const std::string scene = opt.scene.empty() && opt.preset.state ? opt.preset.state->scene : opt.scene;
        auto at_time = scene_at_time(scene, *opt.time);
        if (!at_time) return fail(at_time.error());
        opt.scene = *at_time;
    }
    for (const std::string& path : {opt.out, opt.depth_out})
        if (const std::string problem = path.empty() ? "" : missing_directory(path); !problem.empty()) return fail(problem);
    if (opt.preset.error.empty())
        if (const std::string problem = structure_problem(opt); !problem.empty()) return fail(problem);
    const std::optional<WindowView> window_view = kWindowViewNames.parse(opt.view);
    const CpuView cpu_view = kCpuViewNames.parse(opt.view).value_or(CpuView::Split);  // CLI11 checked the name
    if (opt.rays != "primary" && cpu_view != CpuView::HeatNodes && cpu_view != CpuView::HeatTris)
        return fail("--rays is for --view heat-nodes or heat-tris, not --view " + opt.view);
    if (opt.gpu && (window_view || (cpu_view != CpuView::RayCast && cpu_view != CpuView::HeatLoop &&
                                     cpu_view != CpuView::HeatStack)))
        return fail("--gpu draws --view raycast, heat-loop or heat-stack, not --view " + opt.view);
    if (!opt.gpu && (cpu_view == CpuView::HeatLoop || cpu_view == CpuView::HeatStack) && !window_view)
        return fail("--view " + opt.view + " is the GPU traversal's: add --gpu");
    if ((!opt.slice_axis.empty() || opt.slice_at) && (window_view || cpu_view != CpuView::Slice))
        return fail("--slice-axis and --slice-at are for --view slice, not --view " + opt.view);
    if ((opt.scaling_accel != "bvh" || opt.scaling_max != 10.5e6) && (window_view || cpu_view != CpuView::Scaling))
        return fail("--scaling-accel and --scaling-max are for --view scaling, not --view " + opt.view);
    if (window_view == WindowView::Step) return run_render_step(opt);
    if ((opt.step >= 0 && window_view != WindowView::BuildStep && window_view != WindowView::FillOrder) ||
        !opt.pixel.empty())
        return fail("--step is for --view build-step, step or fill-order, --pixel for --view step");
    if (window_view == WindowView::FillOrder && opt.step > 100)
        return fail("--step " + std::to_string(opt.step) + ": fill-order takes a percentage of the work, 0 to 100");
    using clock = std::chrono::steady_clock;
    if (!opt.preset.error.empty()) return fail("--preset: " + opt.preset.error);
    // The state: the preset's, then what the command line gave.
    AppState state = opt.preset.state.value_or(AppState{});
    if (!opt.scene.empty()) state.scene = opt.scene;
    else if (!opt.preset.state) return fail("no scene: give SCENE (an OBJ file or builtin:NAME) or --preset FILE");

    state.accel = opt.accel;  // already the preset's structure with the flags given applied on top
    auto light = apply_light_flags(opt.light, state.light);
    if (!light) return fail(light.error());
    state.light = *light;
    auto mirrored = apply_mirror_flag(opt.light, state.scene);
    if (!mirrored) return fail(mirrored.error());
    state.scene = *mirrored;
    const HeatRays heat_rays = *kHeatRaysNames.parse(opt.rays);  // CLI11 checked the name
    if (heat_rays == HeatRays::Shadow && !state.light.shadows)
        return fail("--rays shadow: no shadow rays without --shadows on");
    if (heat_rays == HeatRays::Reflection && !state.light.reflections)
        return fail("--rays reflection: no reflection rays without --reflections on");
    if (window_view == WindowView::BuildStep) return run_build_step(opt, std::move(state));
    if (window_view == WindowView::FillOrder && opt.step >= 0) state.view.fill = float(opt.step) / 100.0f;
    if (!opt.draw.empty()) {
        if (!window_view) return fail("--draw is for the window's views (structure, gui, ...), not --view " + opt.view);
        apply_draw_flag(opt.draw, state);
    }
    if (window_view) {
        if (!opt.depth_out.empty()) return fail("--depth-out: only the CPU views write a depth file, not --view " + opt.view);
        return run_window_view(opt, *window_view, std::move(state));
    }
    if (cpu_view == CpuView::Scaling) {
        if (!opt.depth_out.empty()) return fail("--depth-out: --view scaling is a chart, it has no depth to write");
        return run_render_scaling(opt, state);
    }
    if (cpu_view == CpuView::Slice) {
        if (!opt.depth_out.empty()) return fail("--depth-out: --view slice has no depth to write");
        return run_render_slice(opt, state);
    }
    if (opt.gpu) {
        if (!opt.depth_out.empty()) return fail("--depth-out: not with --gpu");
        if (state.light.point_light()) return fail("--gpu shades with the headlight: drop --shadows, --reflections, --light");
        return run_render_gpu(opt, state, cpu_view);
    }

    auto mesh = load_scene_noting(state.scene, "render");
    if (!mesh) return fail(mesh.error());
    auto camera_params = state.camera ? opt.camera.resolve(*state.camera) : opt.camera.resolve(mesh->bounds());
    if (!camera_params) return fail(camera_params.error());
    const Camera camera(*camera_params, opt.width, opt.height);

    const bool needs_raster = cpu_view == CpuView::Raster || cpu_view == CpuView::Split || cpu_view == CpuView::DepthDiff;
    const bool needs_ray = cpu_view != CpuView::Raster || !opt.depth_out.empty();
    const bool count_work = cpu_view == CpuView::HeatNodes || cpu_view == CpuView::HeatTris || cpu_view == CpuView::Split;

    Frame ray_frame, raster_frame;
    WorkSummary work;
    work.accel_name = to_string(state.accel.type);
    if (needs_ray) {
        auto start = clock::now();
        auto accel = [&] {
            const StepProgress progress("render", "building " + std::string(to_string(state.accel.type)));
            return structure_for(state, *mesh);
        }();
        if (!accel) return fail(accel.error());
        const double build_ms = ms_since(start);
        print_memory_budget_note(**accel, "render");
        const std::optional<Lighting> lighting = lighting_for(state.light, *mesh, mesh->bounds());
        start = clock::now();
        ray_frame = ray_cast(**accel, *mesh, camera,
                             {.threads = opt.threads, .count_work = count_work, .lighting = lighting ? &*lighting : nullptr});
        std::fprintf(stderr, "ray cast (%s): build %.1f ms, frame %.1f ms\n", accel_name(state).c_str(), build_ms,
                     ms_since(start));
        work.ray_work = ray_frame.work;
        work.ray_work_counted = count_work;
        if (lighting && lighting->shadows) print_shadow_lesson(measure_shadow_queries(**accel, *mesh, camera, *lighting, opt.threads));
        if (lighting && lighting->reflections && mesh->mirror.empty())
            std::fprintf(stderr, "render: note: %s has no mirror triangles (builtin:cornell-mirror has): no reflections\n",
                         state.scene.c_str());
    }
    if (needs_raster) {
        const auto start = clock::now();
        raster_frame = rasterize(*mesh, camera, &work.raster_work);
        std::fprintf(stderr, "rasterize: %.1f ms\n", ms_since(start));
    }

    Image image;
    switch (cpu_view) {
        case CpuView::RayCast: image = ray_frame.colour; break;
        case CpuView::Raster: image = raster_frame.colour; break;
        case CpuView::Split: image = split_view(raster_frame, ray_frame, work); break;
        case CpuView::DepthDiff: image = depth_diff_view(raster_frame, ray_frame); break;
        case CpuView::Slice:
        case CpuView::HeatLoop:
        case CpuView::HeatStack:
        case CpuView::Scaling: break;  // drawn by run_render_slice, run_render_gpu, run_render_scaling
        case CpuView::HeatNodes:
        case CpuView::HeatTris: {
            const bool nodes = cpu_view == CpuView::HeatNodes;
            const SecondaryWork* secondary = heat_rays == HeatRays::Shadow       ? &ray_frame.shadow
                                             : heat_rays == HeatRays::Reflection ? &ray_frame.reflection
                                                                                 : nullptr;
            const std::vector<uint32_t>& counts =
                secondary ? (nodes ? secondary->nodes : secondary->tests) : (nodes ? ray_frame.nodes : ray_frame.tests);
            const std::string rays = secondary ? std::string(" by ") + std::string(to_string(heat_rays)) + " rays" : "";
            image = heat_view(counts, opt.width, opt.height,
                              (nodes ? "Nodes visited per pixel" : "Triangles tested per pixel") + rays + " (" +
                                  accel_name(state) + ")",
                              opt.heat_max);
            break;
        }
    }

    if (auto err = write_png(image, opt.out)) return fail(err->message);
    std::cout << opt.out << "\n";
    if (needs_raster && needs_ray) {
        const DepthAgreement a = compare_depths(raster_frame, ray_frame);
        std::fprintf(stderr, "raster vs ray cast: depth agrees on %.4f%% of %zu shared pixels (max rel. error %.2e), coverage differs on %.4f%% of pixels\n",
                     a.agreeing_percent(), a.covered_by_both, a.max_relative_error, a.coverage_differs_percent());
    }
    if (!opt.depth_out.empty()) {
        if (auto err = write_pfm(ray_frame.depth, opt.width, opt.height, opt.depth_out)) return fail(err->message);
        std::cout << opt.depth_out << "\n";
    }
    return 0;
}

}  // namespace

Command register_render(CLI::App& app) {
    auto opt = std::make_shared<RenderOptions>();
    CLI::App* sub = app.add_subcommand(
        "render", "Render a view of a scene to a PNG file (no window needed; the window's views through OSMesa)");
    sub->add_option("scene", opt->scene,
                    "OBJ file, or builtin:NAME (e.g. builtin:teapot, builtin:soup?n=1000&seed=7); "
                    "optional with --preset, and replaces the preset's scene when given");
    sub->add_option("--time", opt->time,
                    "A moving scene's time t (builtin:moving, builtin:wave: sets its t=; one period per unit)");
    // Before the structure flags: CLI11 runs option callbacks in the order the
    // options were added, so the flags given apply on top of the preset's structure.
    add_preset_flag(
        *sub, opt->preset, opt->accel,
        "Start from this saved window state (a JSON file, or a shipped preset's name, e.g. 30-grid-stadium): "
        "scene, structure, camera, "
        "overlay and view settings. SCENE, the structure flags and the camera flags given replace its values. "
        "A relative OBJ path in it is relative to the preset's directory if the file is there",
        "render");
    sub->add_option("--out,-o", opt->out, "Output PNG file")->required();
    sub->add_option("--view", opt->view,
                    "raycast | raster | split (raster left, ray cast right, each --width wide) | depth-diff | "
                    "heat-nodes | heat-tris: the CPU renderers; heat-loop | heat-stack (with --gpu); scaling (a log-log chart of "
                    "frame time against triangles: the mesh repeated 1, 2, 4, ... times up to --scaling-max, each "
                    "scene seen whole, rasterized by OpenGL (OSMesa) and the CPU z-buffer and ray cast through "
                    "--scaling-accel's structures, measured now; the table on stderr); slice (a plane across the scene coloured inside / outside by ray parity, --slice-axis, --slice-at; naive or bvh); structure (the window's 3D view with the "
                    "structure overlay) | gui (the whole window frame, panels included) | build-step (the window "
                    "with the BVH construction stepper at --step; with --accel kd or --structure, the tree's node --step) | step (the window with the traversal stepper "
                    "at --step K on the ray of --pixel X,Y, the 3D view seeing the ray from the side: the camera "
                    "turned 35 degrees about up and 15 higher, aimed at the ray's point nearest its target, at 0.6 "
                    "times its distance) | comparison (the window with the comparison panel: every structure built "
                    "and traced on one thread over this view's rays, measured now, and the amortization chart) | "
                    "fill-order (the window split: the CPU rasterizer after --step percent of its triangles, the "
                    "ray caster after --step percent of its pixels, row by row; default: the preset's, else 100) | "
                    "two-bvhs (the window with the two-BVHs panel: the scene's BVH by two builders, median and "
                    "sah-binned unless the preset says, side by side with their SAH costs and nodes per ray): "
                    "the window's OpenGL renderer through OSMesa. Without a preset or camera "
                    "flags, structure/gui frame the scene like the window does")
        ->check(CLI::IsMember(all_views()))
        ->capture_default_str();
    add_draw_flag(*sub, opt->draw,
                  "ray cast when rasterizing the mesh is estimated over 30 ms at 12M triangles a second",
                  "The window's views (structure, gui, ...): ");
    sub->add_option("--width", opt->width, "Image width in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--height", opt->height, "Image height in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--threads", opt->threads, "Ray-casting threads (0 = all cores; more than the cores run on all cores)")
        ->check(whole_number(0, 1024))
        ->capture_default_str();
    sub->add_option("--depth-out", opt->depth_out,
                    "CPU views: also write the ray-cast depth (hit distance t, +inf on a miss) as a PFM file");
    add_light_flags(*sub, opt->light);
    sub->add_flag("--gpu", opt->gpu,
                  "Ray cast on the GPU: the binary BVH traversed by an OpenGL 4.3 compute shader (headless: "
                  "llvmpipe), one invocation per pixel; prints its agreement with the CPU and both times. Views: "
                  "raycast, heat-loop (each invocation's loop iterations: divergence), heat-stack (its deepest stack)");
    sub->add_option("--slice-axis", opt->slice_axis,
                    "slice: the plane is perpendicular to x, y or z (default: the preset's, else z)")
        ->check(CLI::IsMember({"x", "y", "z"}));
    sub->add_option("--slice-at", opt->slice_at,
                    "slice: where along that axis, 0 to 1 of the mesh's box (default: the preset's, else 0.5)")
        ->check(number_between(0, 1));
    sub->add_option("--scaling-accel", opt->scaling_accel,
                    "scaling: the structures to ray cast through, comma-separated (e.g. bvh,kd,grid; each with the "
                    "structure flags if it is --accel's, else its defaults; not naive). Ray casts use --threads, "
                    "builds every core")
        ->capture_default_str();
    sub->add_option("--scaling-max", opt->scaling_max,
                    "scaling: the biggest scene's triangles (copies double while they fit; 10.5M takes about a "
                    "minute here; scenes over the memory budget are left out)")
        ->check(number_between(1, 1e9))
        ->capture_default_str();
    sub->add_option("--rays", opt->rays,
                    "heat-nodes, heat-tris: whose work per pixel: primary (the camera's rays) | shadow (--shadows on) | "
                    "reflection (--reflections on)")
        ->check(CLI::IsMember(kHeatRaysNames.names()))
        ->capture_default_str();
    sub->add_option("--heat-max", opt->heat_max,
                    "heat-nodes, heat-tris: top of the heat-map scale, a count per pixel (default: the image's "
                    "maximum)")
        ->check(number_between(1, 1e9));
    sub->add_option("--step", opt->step,
                    "build-step: which decision of the BVH build to show (0 = the root's), or which node of "
                    "the KD tree or the --structure file's tree (in its numbering); step: events applied "
                    "(0 = before the first, the default; past the end = the final state); fill-order: the "
                    "percentage of each loop's work done (0 to 100)")
        ->check(whole_number(0, INT32_MAX, ">= 0"));
    sub->add_option("--pixel", opt->pixel,
                    "step: pixel X,Y (0,0 = top left) of the --width x --height image whose ray is stepped "
                    "(the ray `trace --pixel X,Y` prints)");
    opt->camera.add_to(*sub);
    add_accel_flags(*sub, opt->accel);
    return {sub, [opt, sub] {
                opt->accel_given = sub->get_option("--accel")->count() > 0;
                return run_render(*opt);
            }};
}

}  // namespace accelviz::cli
