// `accelviz trace SCENE --pixel X,Y --json`: every event of one pixel's ray through
// the chosen structure, then the result and the counters. The same event stream
// the stepper replays (core/traversal/replay.h), from the same traversal code.
// --ray shadow | reflection: the secondary ray the ray caster traces from that
// pixel's hit instead (lighting.h), the shadow ray by the any-hit query.
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
#include "app/cli/light_flags.h"
#include "core/exchange/structure_check.h"
#include "core/geometry/scene.h"
#include "core/render/lighting.h"
#include "core/stepper/stepper.h"
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
    std::string ray_kind = "camera";  ///< --ray: camera | shadow | reflection
    std::string light;                ///< --light X,Y,Z ("": the scene's default light)
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

    Ray ray = picked->ray;
    StopAt query = StopAt::ClosestHit;
    if (!opt.light.empty() && opt.ray_kind != "shadow") return fail("--light is for --ray shadow");
    auto light_settings = apply_light_flags(LightFlags{.shadows = "", .reflections = "", .light = opt.light, .mirror = std::nullopt}, LightSettings{});
    if (!light_settings) return fail(light_settings.error());
    const Vec3 light = to_float(light_position(*light_settings, mesh->bounds()));
    if (opt.ray_kind != "camera") {
        // The secondary ray from the camera ray's hit, made as the ray caster makes it.
        const Hit first = (*accel)->intersect_closest(ray);
        if (!first.found()) return fail("--ray " + opt.ray_kind + ": the ray of pixel " + opt.pixel + " hits nothing");
        const Triangle tri = mesh->triangle(first.tri);
        if (opt.ray_kind == "reflection") {
            ray = reflection_ray(tri, first.u, first.v, ray.dir);
        } else {
            auto to_light = shadow_ray(tri, first.u, first.v, ray.dir, light);
            if (!to_light)
                return fail("--ray shadow: the light is behind the surface pixel " + opt.pixel +
                            " sees (triangle " + std::to_string(first.tri) + "): unlit, no shadow ray");
            ray = *to_light;
            query = StopAt::AnyHit;
        }
    }
    const SteppedRay traced = record_ray(**accel, ray, query);
    const std::vector<TraversalEvent>& events = traced.events;
    const Hit hit = traced.hit;
    RecordingObserver recorder;
    recorder.events = events;
    const Counters counters = recorder.counters();

    if (opt.json) {
        nlohmann::ordered_json out;
        out["scene"] = opt.scene;
        out["triangles"] = mesh->triangle_count();
        out["accel"] = (*accel)->name();
        out["config"] = (*accel)->config();
        out["pixel"] = {x, y};
        out["ray_kind"] = opt.ray_kind;
        out["query"] = query == StopAt::AnyHit ? "any-hit" : "closest-hit";
        out["ray"] = {{"origin", {ray.origin.x, ray.origin.y, ray.origin.z}},
                      {"dir", {ray.dir.x, ray.dir.y, ray.dir.z}},
                      {"t_min", float_to_json(ray.t_min)},
                      {"t_max", float_to_json(ray.t_max)}};
        out["events"] = to_json(events);
        out["result"] = to_json(hit);
        out["counters"] = to_json(counters);
        std::cout << out.dump(1) << "\n";
        return 0;
    }
    std::printf("%s, %zu triangles, %s %s\n", opt.scene.c_str(), mesh->triangle_count(), (*accel)->name().c_str(),
                (*accel)->config().dump().c_str());
    std::printf("pixel (%d, %d): %s ray from (%.9g, %.9g, %.9g) along (%.9g, %.9g, %.9g), t in [%.9g, %.9g], %s\n", x,
                y, opt.ray_kind.c_str(), ray.origin.x, ray.origin.y, ray.origin.z, ray.dir.x, ray.dir.y, ray.dir.z,
                ray.t_min, ray.t_max, query == StopAt::AnyHit ? "any-hit (stops at the first hit)" : "closest-hit");
    for (size_t i = 0; i < events.size(); ++i) std::printf("%6zu  %s\n", i, describe(events[i]).c_str());
    if (hit.found())
        std::printf("%s: triangle %u at t = %.9g (u = %.9g, v = %.9g)\n",
                    query == StopAt::AnyHit ? "blocked" : "hit", hit.tri, hit.t, hit.u, hit.v);
    else
        std::printf("%s\n", query == StopAt::AnyHit ? "free: the light is visible" : "miss");
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
    sub->add_option("--ray", opt->ray_kind,
                    "camera: the pixel's ray | shadow: from its hit to the light, by the any-hit query (it stops at "
                    "the first triangle in the way) | reflection: the ray its hit would reflect, as off a mirror")
        ->check(CLI::IsMember({"camera", "shadow", "reflection"}))
        ->capture_default_str();
    sub->add_option("--light", opt->light,
                    "--ray shadow: the point light X,Y,Z (default: inside the scene's box, near its top and front right)");
    opt->camera.add_to(*sub);
    add_accel_flags(*sub, opt->accel);
    return {sub, [opt] { return run_trace(*opt); }};
}

}  // namespace accelviz::cli
