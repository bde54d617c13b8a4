/// `accelviz bench-motion SCENE`: the lecture's "BVHs handle dynamic scenes well",
/// measured. A moving scene (builtin:moving, builtin:wave) is played over one period
/// in --frames steps; at each time the BVH is refitted (the tree of the first time,
/// its boxes recomputed) and rebuilt, the KD tree and the grid rebuilt, and each
/// traces the same camera's rays. Per time: update ms, SAH cost (the BVHs), Mrays/s;
/// then where a rebuild starts to pay for itself (update + trace per frame).

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>

#include <nlohmann/json.hpp>
#include <tbb/global_control.h>

#include "app/cli/accel_flags.h"
#include "app/cli/camera_flags.h"
#include "app/cli/commands.h"
#include "app/cli/flag_checks.h"
#include "app/cli/ray_batch.h"
#include "core/accel/bvh.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/chart.h"
#include "core/render/image.h"
#include "core/render/ray_caster.h"

namespace accelviz::cli {

namespace {

struct BenchMotionOptions {
    std::string scene;
    int frames = 8;
    int width = 640, height = 360;
    int threads = 1;
    bool json = false;
    std::string chart;  ///< --chart: a PNG of the figures over the period
    CameraFlags camera;
};

/// The figures over the period as two charts, one above the other: the BVH's SAH cost
/// refitted and rebuilt, and each method's cost of a frame (update + trace), with the
/// time from which a rebuild pays marked.
Image motion_chart(const nlohmann::ordered_json& frames, const char* const methods[4],
                   std::optional<double> rebuild_pays_from, const std::string& scene) {
    const Rgb colours[4] = {{220, 110, 40}, {40, 110, 200}, {60, 160, 80}, {140, 90, 170}};
    LineChart cost, frame;
    cost.title = "SAH cost of the BVH over the period (" + scene + ")";
    cost.x_label = "time t";
    cost.y_label = "SAH cost";
    frame.title = "milliseconds per frame: update (refit or build) + trace";
    frame.x_label = "time t";
    frame.y_label = "ms";
    for (int m = 0; m < 4; ++m) {
        ChartSeries series{methods[m], colours[m], {}, {}};
        ChartSeries sah{methods[m], colours[m], {}, {}};
        for (const auto& f : frames) {
            const auto& u = f[methods[m]];
            series.x.push_back(f["t"].get<double>());
            series.y.push_back(u["update_ms"].get<double>() + u["trace_ms"].get<double>());
            if (u.contains("sah_cost")) {
                sah.x.push_back(f["t"].get<double>());
                sah.y.push_back(u["sah_cost"].get<double>());
            }
        }
        frame.series.push_back(std::move(series));
        if (!sah.x.empty()) cost.series.push_back(std::move(sah));
    }
    if (rebuild_pays_from) {
        frame.mark_x = rebuild_pays_from;
        frame.mark_label = "a rebuild pays from here";
    }
    Image out(1280, 720);
    draw_line_chart(out, 0, 0, 1280, 360, cost);
    draw_line_chart(out, 0, 360, 1280, 360, frame);
    return out;
}


double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// One way of keeping up with the scene, at one time.
struct Update {
    double update_ms = 0;  ///< refit or build
    double trace_ms = 0;   ///< the camera's rays, closest hit
    double sah_cost = 0;   ///< BVHs only
    uint64_t hits = 0;
};

Update trace_with(const Accelerator& accel, const std::vector<Ray>& rays, int threads, Update update) {
    RayResults results(rays.size());
    const auto start = std::chrono::steady_clock::now();
    for_each_ray_chunk(rays.size(), threads, [&](size_t begin, size_t end) {
        for (size_t i = begin; i < end; ++i) results.tri[i] = accel.intersect_closest(rays[i]).tri;
    });
    update.trace_ms = ms_since(start);
    update.hits = results.hit_count();
    return update;
}

int run_bench_motion(const BenchMotionOptions& opt) {
    auto fail = [](const std::string& message) {
        std::cerr << "accelviz bench-motion: " << message << "\n";
        return 1;
    };
    if (auto first = scene_at_time(opt.scene, 0.0); !first) return fail(first.error());
    const int threads = effective_threads(opt.threads);
    const tbb::global_control build_threads(tbb::global_control::max_allowed_parallelism, size_t(threads));

    // The camera of the first time, kept: the scene moves, the viewer does not.
    std::vector<Ray> rays;
    std::shared_ptr<const Accelerator> refit_tree;  // the first time's BVH, refitted from time to time
    const char* kMethods[] = {"bvh refit", "bvh rebuild", "kd rebuild", "grid rebuild"};
    nlohmann::ordered_json frames = nlohmann::ordered_json::array();
    for (int k = 0; k <= opt.frames; ++k) {
        const double t = double(k) / opt.frames;
        if (isatty(STDERR_FILENO)) std::fprintf(stderr, "bench-motion: time %d of %d\n", k, opt.frames);  // (a terminal only)
        const std::string source = *scene_at_time(opt.scene, t);
        auto mesh = load_scene(source);
        if (!mesh) return fail(mesh.error());
        if (rays.empty()) {
            auto camera = opt.camera.resolve(mesh->bounds());
            if (!camera) return fail(camera.error());
            rays = camera_rays(Camera(*camera, opt.width, opt.height));
        }
        Update updates[4];
        // BVH refit (at the first time: the build it refits from later). refit_accelerator
        // copies the tree before refitting it; its refit_ms times the refit alone.
        if (!refit_tree) {
            AccelConfig bvh;
            bvh.type = AccelType::Bvh;
            const auto start = std::chrono::steady_clock::now();
            auto built = build_accelerator(*mesh, bvh);
            if (!built) return fail(built.error());
            updates[0].update_ms = ms_since(start);
            refit_tree = std::move(*built);
        } else {
            auto next = refit_accelerator(*refit_tree, *mesh);
            if (!next) return fail(next.error());
            refit_tree = std::move(*next);
            updates[0].update_ms = structure_if<Bvh>(*refit_tree)->build_stats.refit_ms;
        }
        updates[0].sah_cost = structure_if<Bvh>(*refit_tree)->build_stats.sah_cost;
        updates[0] = trace_with(*refit_tree, rays, threads, updates[0]);
        // The rebuilds.
        const AccelType rebuilt[] = {AccelType::Bvh, AccelType::Kd, AccelType::Grid};
        for (int m = 0; m < 3; ++m) {
            AccelConfig config;
            config.type = rebuilt[m];
            const auto start = std::chrono::steady_clock::now();
            auto accel = build_accelerator(*mesh, config);
            if (!accel) return fail(accel.error());
            updates[m + 1].update_ms = ms_since(start);
            if (const Bvh* tree = structure_if<Bvh>(**accel)) updates[m + 1].sah_cost = tree->build_stats.sah_cost;
            updates[m + 1] = trace_with(**accel, rays, threads, updates[m + 1]);
        }
        nlohmann::ordered_json frame;
        frame["t"] = t;
        for (int m = 0; m < 4; ++m) {
            nlohmann::ordered_json u;
            u["update_ms"] = updates[m].update_ms;
            u["trace_ms"] = updates[m].trace_ms;
            u["mrays_per_s"] = double(rays.size()) / (updates[m].trace_ms * 1e3);
            if (m < 2) u["sah_cost"] = updates[m].sah_cost;
            u["hits"] = updates[m].hits;
            frame[kMethods[m]] = u;
        }
        frames.push_back(frame);
        if (updates[0].hits != updates[1].hits || updates[0].hits != updates[2].hits || updates[0].hits != updates[3].hits)
            return fail("the structures disagree on how many rays hit at t = " + std::to_string(t) + " (a bug)");
    }

    nlohmann::ordered_json out;
    out["scene"] = opt.scene;
    out["frames"] = opt.frames;
    out["threads"] = threads;
    out["width"] = opt.width;
    out["height"] = opt.height;
    out["times"] = frames;
    // Where a rebuild pays: the first time at which refit + trace costs more than rebuild + trace.
    std::optional<double> rebuild_pays_from;
    double pay_rebuild = 0, pay_refit = 0;
    for (const auto& frame : frames) {
        const double refit = frame[kMethods[0]]["update_ms"].get<double>() + frame[kMethods[0]]["trace_ms"].get<double>();
        const double rebuild = frame[kMethods[1]]["update_ms"].get<double>() + frame[kMethods[1]]["trace_ms"].get<double>();
        if (frame["t"].get<double>() > 0 && rebuild < refit) {
            rebuild_pays_from = frame["t"].get<double>();
            pay_rebuild = rebuild;
            pay_refit = refit;
            break;
        }
    }
    if (!opt.chart.empty()) {
        if (auto err = write_png(motion_chart(frames, kMethods, rebuild_pays_from, opt.scene), opt.chart))
            return fail(err->message);
        std::fprintf(stderr, "bench-motion: chart written to %s\n", opt.chart.c_str());
    }
    if (opt.json) {
        std::cout << out.dump(2) << "\n";
        return 0;
    }
    std::printf("scene %s, %d times over one period, %dx%d, %d thread%s; ms to update / ms to trace (SAH cost)\n",
                opt.scene.c_str(), opt.frames + 1, opt.width, opt.height, threads, threads == 1 ? "" : "s");
    std::printf("(at t = 0 the refit column's update is the build it refits from)\n");
    std::printf("%6s  %-24s %-24s %-16s %-16s\n", "t", kMethods[0], kMethods[1], kMethods[2], kMethods[3]);
    for (const auto& frame : frames) {
        auto cell = [&](const char* method) {
            const auto& u = frame[method];
            char text[64];
            if (u.contains("sah_cost"))
                std::snprintf(text, sizeof text, "%.1f / %.1f (%.1f)", u["update_ms"].get<double>(),
                              u["trace_ms"].get<double>(), u["sah_cost"].get<double>());
            else
                std::snprintf(text, sizeof text, "%.1f / %.1f", u["update_ms"].get<double>(), u["trace_ms"].get<double>());
            return std::string(text);
        };
        std::printf("%6.3f  %-24s %-24s %-16s %-16s\n", frame["t"].get<double>(), cell(kMethods[0]).c_str(),
                    cell(kMethods[1]).c_str(), cell(kMethods[2]).c_str(), cell(kMethods[3]).c_str());
    }
    if (rebuild_pays_from)
        std::printf("a rebuild pays from t = %.3f: %.1f ms a frame against the refit tree's %.1f\n",
                    *rebuild_pays_from, pay_rebuild, pay_refit);
    else
        std::printf("the refit tree stays cheaper (update + trace) than a rebuild at every time\n");
    return 0;
}

}  // namespace

Command register_bench_motion(CLI::App& app) {
    auto opt = std::make_shared<BenchMotionOptions>();
    CLI::App* sub = app.add_subcommand(
        "bench-motion",
        "A moving scene over one period: BVH refit against BVH, KD and grid rebuilds, time by time");
    sub->add_option("scene", opt->scene, "A moving scene: builtin:moving or builtin:wave?mesh=PATH (its t is set)")
        ->required();
    sub->add_option("--frames", opt->frames, "Steps over the period (times 0, 1/N, ..., 1)")
        ->check(whole_number(1, 1000))
        ->capture_default_str();
    sub->add_option("--width", opt->width, "Image width in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--height", opt->height, "Image height in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--threads", opt->threads, "Threads for building and tracing (0 = all cores)")
        ->check(whole_number(0, 1024))
        ->capture_default_str();
    sub->add_flag("--json", opt->json, "One JSON object instead of a table");
    sub->add_option("--chart", opt->chart,
                    "Also write a PNG: the BVH's SAH cost refitted and rebuilt over the period, and each method's "
                    "ms per frame (update + trace), the time from which a rebuild pays marked");
    opt->camera.add_to(*sub);
    return {sub, [opt] { return run_bench_motion(*opt); }};
}

}  // namespace accelviz::cli
