// `accelviz trace SCENE --pixel X,Y --json`: every event of one pixel's ray through
// the chosen structure, then the result and the counters. The same event stream
// the stepper replays (core/traversal/replay.h), from the same traversal code.
#include <cstdio>
#include <iostream>
#include <memory>

#include <nlohmann/json.hpp>

#include "app/cli/accel_flags.h"
#include "app/cli/camera_flags.h"
#include "app/cli/commands.h"
#include "app/cli/progress.h"
#include "app/cli/scene_input.h"
#include "app/cli/flag_checks.h"
#include "core/exchange/structure_check.h"
#include "core/geometry/scene.h"
#include "core/traversal/event_json.h"

namespace accelviz::cli {
namespace {

struct TraceOptions {
    std::string scene;
    std::string pixel;
    int width = 1280, height = 720;
    bool json = false;
    CameraFlags camera;
    AccelConfig accel;
};

int run_trace(const TraceOptions& opt) {
    auto fail = [](const std::string& message) {
        std::cerr << "accelviz trace: " << message << "\n";
        return 1;
    };
    auto picked = pixel_ray(opt.scene, opt.pixel, opt.width, opt.height, opt.camera);
    if (!picked) return fail(picked.error());
    const Mesh* mesh = &picked->mesh;
    const int x = picked->x, y = picked->y;
    auto accel = [&] {
        if (!opt.accel.structure_file.empty()) return load_structure_file(opt.accel.structure_file, *mesh, opt.scene);
        const StepProgress progress("trace", "building " + std::string(to_string(opt.accel.type)));
        return build_accelerator(*mesh, opt.accel);
    }();
    if (!accel) return fail(accel.error());
    print_memory_budget_note(**accel, "trace");

    const Ray ray = picked->ray;
    RecordingObserver recorder;
    const Hit hit = (*accel)->intersect_closest(ray, recorder);
    const Counters counters = recorder.counters();

    if (opt.json) {
        nlohmann::ordered_json out;
        out["scene"] = opt.scene;
        out["triangles"] = mesh->triangle_count();
        out["accel"] = (*accel)->name();
        out["config"] = (*accel)->config();
        out["pixel"] = {x, y};
        out["ray"] = {{"origin", {ray.origin.x, ray.origin.y, ray.origin.z}},
                      {"dir", {ray.dir.x, ray.dir.y, ray.dir.z}},
                      {"t_min", float_to_json(ray.t_min)},
                      {"t_max", float_to_json(ray.t_max)}};
        out["events"] = to_json(recorder.events);
        out["result"] = to_json(hit);
        out["counters"] = to_json(counters);
        std::cout << out.dump(1) << "\n";
        return 0;
    }
    std::printf("%s, %zu triangles, %s %s\n", opt.scene.c_str(), mesh->triangle_count(), (*accel)->name().c_str(),
                (*accel)->config().dump().c_str());
    std::printf("pixel (%d, %d): ray from (%.9g, %.9g, %.9g) along (%.9g, %.9g, %.9g)\n", x, y, ray.origin.x,
                ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z);
    for (size_t i = 0; i < recorder.events.size(); ++i)
        std::printf("%6zu  %s\n", i, describe(recorder.events[i]).c_str());
    if (hit.found()) std::printf("hit: triangle %u at t = %.9g (u = %.9g, v = %.9g)\n", hit.tri, hit.t, hit.u, hit.v);
    else std::printf("miss\n");
    std::printf("counters: %s\n", to_json(counters).dump().c_str());
    return 0;
}

}  // namespace

Command register_trace(CLI::App& app) {
    auto opt = std::make_shared<TraceOptions>();
    CLI::App* sub = app.add_subcommand("trace", "Print every traversal event of one pixel's ray (and the result)");
    sub->add_option("scene", opt->scene, "OBJ file, or builtin:NAME (e.g. builtin:teapot)")->required();
    sub->add_option("--pixel", opt->pixel, "Pixel X,Y (0,0 = top left)")->required();
    sub->add_option("--width", opt->width, "Image width in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--height", opt->height, "Image height in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_flag("--json", opt->json, "One JSON object: events (array), result, counters");
    opt->camera.add_to(*sub);
    add_accel_flags(*sub, opt->accel);
    return {sub, [opt] { return run_trace(*opt); }};
}

}  // namespace accelviz::cli
