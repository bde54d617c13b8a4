// `accelviz render SCENE --out FILE.png`: the CPU views, rendered headless.
#include <chrono>
#include <cstdio>
#include <iostream>

#include "app/cli/accel_flags.h"
#include "app/cli/camera_flags.h"
#include "app/cli/commands.h"
#include "app/gui/headless.h"
#include "app/gui/stepper_panel.h"
#include "core/geometry/scene.h"
#include "core/render/ray_caster.h"
#include "core/render/views.h"

namespace accelviz::cli {
namespace {

struct RenderOptions {
    std::string scene;
    std::string out;
    std::string view = "split";
    std::string depth_out;
    int width = 1280, height = 720;
    int threads = 0;
    double heat_max = 0;
    CameraFlags camera;
    AccelConfig accel;
    int step = -1;              ///< build-step: the decision to show; step: events applied (-1: not given)
    std::string pixel;          ///< step: the pixel whose ray is stepped
    bool accel_given = false;   ///< --accel was on the command line
};

const std::vector<std::string> kViews = {"raycast",   "raster",    "split",     "depth-diff",
                                         "heat-nodes", "heat-tris", "build-step", "step"};

double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// `--view build-step --step K`: the window's frame (OSMesa) with the construction
/// stepper at decision K of the BVH build.
int run_build_step(const RenderOptions& opt) {
    if (opt.step < 0) {
        std::cerr << "accelviz render: --view build-step needs --step K (the build decision to show, 0 = the root)\n";
        return 1;
    }
    AppState state;
    state.scene = opt.scene;
    state.accel = opt.accel;
    if (!opt.accel_given) state.accel.type = "bvh";
    if (state.accel.type != "bvh") {
        std::cerr << "accelviz render: --view build-step steps a BVH build (--accel bvh, not " << state.accel.type << ")\n";
        return 1;
    }
    // The shared flags (--leaf-size, --cost-*) as the tree and the chart take them.
    if (state.accel.leaf_size) state.accel.bvh.max_leaf_size = *state.accel.leaf_size;
    if (state.accel.cost_trav) state.accel.bvh.cost_trav = *state.accel.cost_trav;
    if (state.accel.cost_isect) state.accel.bvh.cost_isect = *state.accel.cost_isect;
    state.build_step.active = true;
    state.build_step.step = opt.step;
    if (!opt.camera.eye.empty() || !opt.camera.target.empty() || !opt.camera.up.empty() || opt.camera.fov) {
        auto mesh = load_scene(opt.scene);
        if (!mesh) { std::cerr << "accelviz render: " << mesh.error() << "\n"; return 1; }
        auto camera = opt.camera.resolve(mesh->bounds());
        if (!camera) { std::cerr << "accelviz render: " << camera.error() << "\n"; return 1; }
        state.camera = *camera;
    }
    auto image = render_gui_view_headless(state, "build-step", opt.width, opt.height);
    if (!image) { std::cerr << "accelviz render: " << image.error() << "\n"; return 1; }
    if (auto err = write_png(*image, opt.out)) { std::cerr << "accelviz render: " << err->message << "\n"; return 1; }
    std::cout << opt.out << "\n";
    return 0;
}

/// `--view step`: the window's frame (OSMesa) with the stepper open at step K on
/// the ray of pixel X,Y of a width x height image under the camera flags (the ray
/// `trace --pixel X,Y` prints), the 3D view looking at it from the side.
int run_render_step(const RenderOptions& opt) {
    auto fail = [](const std::string& message) {
        std::cerr << "accelviz render: " << message << "\n";
        return 1;
    };
    if (opt.pixel.empty()) return fail("--view step needs --pixel X,Y (the ray to step)");
    int x = 0, y = 0;
    if (!parse_pixel(opt.pixel, x, y)) return fail("--pixel: expected X,Y (two integers), got '" + opt.pixel + "'");
    if (x < 0 || x >= opt.width || y < 0 || y >= opt.height)
        return fail("--pixel " + opt.pixel + " is outside the " + std::to_string(opt.width) + "x" +
                    std::to_string(opt.height) + " image");
    auto mesh = load_scene(opt.scene);
    if (!mesh) return fail(mesh.error());
    auto camera_params = opt.camera.resolve(mesh->bounds());
    if (!camera_params) return fail(camera_params.error());
    AppState state;
    state.scene = opt.scene;
    state.accel = opt.accel;
    const Ray ray = Camera(*camera_params, opt.width, opt.height).ray(x, y);
    state.camera = stepper_side_view(*camera_params, ray);
    state.overlay.mesh_opacity = 0.5f;  // as the window does when the stepper opens: the boxes lie inside the mesh
    state.stepper.open = true;
    state.stepper.ray = ray;
    state.stepper.pixel = std::array<int, 2>{x, y};
    state.stepper.step = opt.step < 0 ? 0 : size_t(opt.step);
    auto image = render_gui_view_headless(state, "step", opt.width, opt.height);
    if (!image) return fail(image.error());
    if (auto err = write_png(*image, opt.out)) return fail(err->message);
    std::cout << opt.out << "\n";
    return 0;
}

int run_render(const RenderOptions& opt) {
    if (opt.view == "build-step") return run_build_step(opt);
    if (opt.view == "step") return run_render_step(opt);
    if (opt.step >= 0 || !opt.pixel.empty()) {
        std::cerr << "accelviz render: --step is for --view build-step or step, --pixel for --view step\n";
        return 1;
    }
    using clock = std::chrono::steady_clock;
    auto mesh = load_scene(opt.scene);
    if (!mesh) { std::cerr << "accelviz render: " << mesh.error() << "\n"; return 1; }
    auto camera_params = opt.camera.resolve(mesh->bounds());
    if (!camera_params) { std::cerr << "accelviz render: " << camera_params.error() << "\n"; return 1; }
    const Camera camera(*camera_params, opt.width, opt.height);

    const bool needs_raster = opt.view == "raster" || opt.view == "split" || opt.view == "depth-diff";
    const bool needs_ray = opt.view != "raster" || !opt.depth_out.empty();
    const bool count_work = opt.view == "heat-nodes" || opt.view == "heat-tris" || opt.view == "split";

    Frame ray_frame, raster_frame;
    WorkSummary work;
    work.accel_name = opt.accel.type;
    if (needs_ray) {
        auto start = clock::now();
        auto accel = build_accelerator(*mesh, opt.accel);
        if (!accel) { std::cerr << "accelviz render: " << accel.error() << "\n"; return 1; }
        const double build_ms = ms_since(start);
        start = clock::now();
        ray_frame = ray_cast(**accel, make_triangles(*mesh), camera, {.threads = opt.threads, .count_work = count_work});
        std::fprintf(stderr, "ray cast (%s): build %.1f ms, frame %.1f ms\n", opt.accel.type.c_str(), build_ms,
                     ms_since(start));
        work.ray_work = ray_frame.work;
        work.ray_work_counted = count_work;
    }
    if (needs_raster) {
        const auto start = clock::now();
        raster_frame = rasterize(*mesh, camera, &work.raster_work);
        std::fprintf(stderr, "rasterize: %.1f ms\n", ms_since(start));
    }

    Image image;
    if (opt.view == "raycast") image = ray_frame.colour;
    else if (opt.view == "raster") image = raster_frame.colour;
    else if (opt.view == "split") image = split_view(raster_frame, ray_frame, work);
    else if (opt.view == "depth-diff") image = depth_diff_view(raster_frame, ray_frame);
    else if (opt.view == "heat-nodes")
        image = heat_view(ray_frame.nodes, opt.width, opt.height, "Nodes visited per pixel (" + opt.accel.type + ")", opt.heat_max);
    else if (opt.view == "heat-tris")
        image = heat_view(ray_frame.tests, opt.width, opt.height, "Triangles tested per pixel (" + opt.accel.type + ")", opt.heat_max);

    if (auto err = write_png(image, opt.out)) { std::cerr << "accelviz render: " << err->message << "\n"; return 1; }
    std::cout << opt.out << "\n";
    if (needs_raster && needs_ray) {
        const DepthAgreement a = compare_depths(raster_frame, ray_frame);
        std::fprintf(stderr, "raster vs ray cast: depth agrees on %.4f%% of %zu shared pixels (max rel. error %.2e), coverage differs on %.4f%% of pixels\n",
                     a.agreeing_percent(), a.covered_by_both, a.max_relative_error, a.coverage_differs_percent());
    }
    if (!opt.depth_out.empty()) {
        if (auto err = write_pfm(ray_frame.depth, opt.width, opt.height, opt.depth_out)) {
            std::cerr << "accelviz render: " << err->message << "\n";
            return 1;
        }
        std::cout << opt.depth_out << "\n";
    }
    return 0;
}

}  // namespace

Command register_render(CLI::App& app) {
    auto opt = std::make_shared<RenderOptions>();
    CLI::App* sub = app.add_subcommand("render", "Render a view of a scene to a PNG file (no window needed)");
    sub->add_option("scene", opt->scene, "OBJ file, or builtin:NAME (e.g. builtin:teapot, builtin:soup?n=1000&seed=7)")
        ->required();
    sub->add_option("--out,-o", opt->out, "Output PNG file")->required();
    sub->add_option("--view", opt->view,
                    "raycast | raster | split (raster left, ray cast right, each --width wide) | depth-diff | "
                    "heat-nodes | heat-tris | build-step (the window with the BVH construction stepper at --step) | "
                    "step (the window with the traversal stepper at --step K on the ray of --pixel X,Y, the 3D view "
                    "seeing the ray from the side: the camera turned 35 degrees about up and 15 higher, aimed at the "
                    "ray's point nearest its target, at 0.6 times its distance)")
        ->check(CLI::IsMember(kViews))
        ->capture_default_str();
    sub->add_option("--width", opt->width, "Image width in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
    sub->add_option("--height", opt->height, "Image height in pixels")->check(CLI::Range(1, 16384))->capture_default_str();
    sub->add_option("--threads", opt->threads, "Ray-casting threads (0 = all cores)")->check(CLI::Range(0, 1024))
        ->capture_default_str();
    sub->add_option("--depth-out", opt->depth_out,
                    "Also write the ray-cast depth (hit distance t, +inf on a miss) as a PFM file");
    sub->add_option("--heat-max", opt->heat_max, "Top of the heat-map scale (default: the image's maximum)")
        ->check(CLI::NonNegativeNumber);
    sub->add_option("--step", opt->step,
                    "build-step: which decision of the BVH build to show (0 = the root's); step: events applied "
                    "(0 = before the first, the default; past the end = the final state)")
        ->check(CLI::NonNegativeNumber);
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
