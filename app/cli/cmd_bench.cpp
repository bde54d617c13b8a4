// `accelviz bench SCENE [structure flags] [camera flags] --json`: how fast the chosen
// structure builds and traces one primary ray per pixel, as one JSON object (or a
// table). With --reference embree (when built with Embree), Embree 3 traces the same
// rays in the same process, so the two speeds are compared side by side.
//
// Method: the rays are generated once, before timing (both structures trace the
// same array, in the ray caster's 16x16 tiles); frame_ms times tracing only, and
// build_ms the whole build (mesh to structure), on the same number of threads. Both are wall-clock medians over
// --repeat runs; *_cpu_ms are the process's CPU time over the same runs (which, on a
// machine shared with other work, is the steadier figure for one thread). per_ray is
// the work behind them (nodes visited, box and triangle tests, mailbox skips), from
// one more, untimed pass with the counting observer. With a reference, ours and the
// reference alternate run by run (build, build, ..., trace, trace, ...), and each ratio
// is the median of the run-by-run ratios (each of our runs against the reference's run
// right after it): a machine whose speed drifts, or a burst of load from elsewhere,
// then spoils a pair, not the ratio.
#include <time.h>
#include <unistd.h>

#include <algorithm>
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
#include "app/cli/scene_input.h"
#include "app/cli/embree_reference.h"
#include "app/gl/gpu_ray_caster.h"
#include "app/platform/osmesa_context.h"
#include "app/cli/flag_checks.h"
#include "app/cli/ray_batch.h"
#include "core/accel/bvh.h"
#include "core/accel/bvh_build.h"
#include "core/accel/factory.h"
#include "core/geometry/scene.h"
#include "core/render/ray_caster.h"

namespace accelviz::cli {
namespace {

struct BenchOptions {
    std::string scene;
    int width = 1280, height = 720;
    int threads = 1;
    int repeat = 5;
    bool json = false;
    std::string reference;
    int embree_width = 0;  ///< children per node of Embree's BVH: 4, 8, or 0 = Embree's choice
    std::string refit_from;  ///< a moving scene's earlier state: build over it, refit to `scene` (bvh only)
    std::optional<double> time;  ///< --time: the moving scene's t (scene_at_time)
    bool gpu = false;            ///< --gpu: also the compute shader's traversal of the same rays
    CameraFlags camera;
    AccelConfig accel;
};


double ms_since(std::chrono::steady_clock::time_point start) {
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// CPU time of the whole process (all threads), in ms. On a shared machine the wall
/// time includes the time other programs had the cores; this does not.
double process_cpu_ms() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

double median(std::vector<double> values) {
    std::sort(values.begin(), values.end());
    const size_t n = values.size();
    return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// --gpu: the binary BVH traversed by the compute shader (a headless OpenGL context), the
/// same rays as ours `repeat` times: the median ms from dispatch to results read back,
/// and how far its answers agree with ours (`ours`: the CPU's triangle and t per ray).
Expected<nlohmann::ordered_json> gpu_figures(const Bvh& bvh, const std::vector<Ray>& rays, int width, int height,
                                             int repeat, const RayResults& ours) {
    auto context = OsMesaContext::create(1, 1);
    if (!context) return Error{context.error()};
    auto caster = GpuRayCaster::create();
    if (!caster) return Error{caster.error()};
    if (auto err = (*caster)->upload(bvh)) return *err;
    std::vector<double> frame_ms;
    GpuCast cast;
    for (int run = 0; run < repeat; ++run) {
        cast = (*caster)->cast(rays, width, height);
        frame_ms.push_back(cast.gpu_ms);
    }
    const GpuAgreement agree = compare_with_cpu(cast, ours.tri, ours.t);
    const double ms = median(frame_ms);
    nlohmann::ordered_json out;
    out["device"] = (*context)->description();
    out["frame_ms"] = ms;
    out["mrays_per_s"] = double(cast.tri.size()) / (ms * 1e3);
    out["same_triangle_share"] = agree.same_share();
    out["max_relative_t"] = agree.max_relative_t;
    return out;
}

/// The median over runs of numerator_ms[i] / denominator_ms[i]: the two runs of a pair
/// ran back to back, under the same load.
double median_of_run_ratios(const std::vector<double>& numerator_ms, const std::vector<double>& denominator_ms) {
    std::vector<double> ratios;
    for (size_t i = 0; i < std::min(numerator_ms.size(), denominator_ms.size()); ++i)
        ratios.push_back(numerator_ms[i] / denominator_ms[i]);
    return ratios.empty() ? 0.0 : median(ratios);
}

/// Progress lines go to stderr, and only to a terminal (never into a captured log).
void progress(const char* format, const std::string& what, int run, int runs) {
    static const bool to_terminal = isatty(STDERR_FILENO) != 0;
    if (to_terminal) std::fprintf(stderr, format, what.c_str(), run, runs);
}

/// Timings and results of one structure.
struct Measured {
    std::vector<double> build_ms, frame_ms;
    std::vector<double> build_cpu_ms, frame_cpu_ms;  ///< process CPU time of the same runs
    RayResults results;
    double mrays_per_s(size_t rays) const { return double(rays) / (median(frame_ms) * 1e3); }
    /// Rays per second of process CPU time: on one thread, the speed without the time
    /// other programs had the core; on N threads, rays per CPU-second (not per second).
    double mrays_per_cpu_s(size_t rays) const { return double(rays) / (median(frame_cpu_ms) * 1e3); }
};

nlohmann::ordered_json summary(const Measured& m, size_t rays) {
    nlohmann::ordered_json j;
    j["build_ms"] = median(m.build_ms);
    j["frame_ms"] = median(m.frame_ms);
    j["mrays_per_s"] = m.mrays_per_s(rays);
    j["mrays_per_cpu_s"] = m.mrays_per_cpu_s(rays);
    j["hit_count"] = m.results.hit_count();
    j["depth_sum"] = m.results.depth_sum();
    j["build_cpu_ms"] = median(m.build_cpu_ms);
    j["frame_cpu_ms"] = median(m.frame_cpu_ms);
    j["build_ms_runs"] = m.build_ms;
    j["frame_ms_runs"] = m.frame_ms;
    j["build_cpu_ms_runs"] = m.build_cpu_ms;
    j["frame_cpu_ms_runs"] = m.frame_cpu_ms;
    return j;
}

/// Times `work` (wall clock and the process's CPU time) into the two lists.
template <class Work>
void timed(std::vector<double>& wall_ms, std::vector<double>& cpu_ms, Work&& work) {
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_ms();
    work();
    cpu_ms.push_back(process_cpu_ms() - cpu_start);
    wall_ms.push_back(ms_since(start));
}

/// The work behind the times, per ray: one more (untimed) pass with the counting
/// observer, through the same traversal code.
nlohmann::ordered_json work_per_ray(const Accelerator& accel, const std::vector<Ray>& rays) {
    Counters work;
    for (const Ray& ray : rays) {
        CountingObserver counter;
        accel.intersect_closest(ray, counter);
        work += counter.counters;
    }
    const double per_ray = 1.0 / double(std::max<size_t>(rays.size(), 1));
    return {{"nodes_visited", double(work.nodes_visited) * per_ray},
            {"box_tests", double(work.box_tests) * per_ray},
            {"triangle_tests", double(work.triangle_tests) * per_ray},
            {"mailbox_skips", double(work.mailbox_skips) * per_ray}};
}

/// The reference's figures, with how they compare with ours.
nlohmann::ordered_json reference_json(const EmbreeReference& reference, const Measured& embree, const Measured& ours,
                                      size_t rays) {
    size_t same = 0;
    for (size_t i = 0; i < rays; ++i) same += embree.results.tri[i] == ours.results.tri[i];
    nlohmann::ordered_json ref;
    ref["name"] = "embree";
    ref["version"] = EmbreeReference::version();
    ref["build_quality"] = "high";
    ref["bvh"] = reference.bvh_description();
    ref["call"] = "rtcIntersect1, one ray per call";
    const nlohmann::ordered_json figures = summary(embree, rays);  // (items() does not keep a temporary alive)
    for (const auto& [key, value] : figures.items()) ref[key] = value;
    ref["same_triangle_percent"] = 100.0 * double(same) / double(rays);
    ref["speed_ratio"] = median_of_run_ratios(embree.frame_ms, ours.frame_ms);  // our speed / Embree's
    ref["build_ratio"] = median_of_run_ratios(ours.build_ms, embree.build_ms);  // our build time / Embree's
    return ref;
}

/// The table `bench` prints without --json: the same figures as the JSON.
void print_table(const BenchOptions& opt, const nlohmann::ordered_json& out, size_t triangles) {
    const int threads = out["threads"].get<int>();
    const std::string asked = threads == opt.threads ? ""
                              : opt.threads == 0 ? " (0 = all cores)"
                                                 : " (" + std::to_string(opt.threads) + " asked: all cores)";
    const std::string name = out["accel"].get<std::string>();
    std::printf("scene      %s (%zu triangles), %dx%d, %d thread%s%s, median of %d\n",
                out["scene"].get<std::string>().c_str(), triangles,
                opt.width, opt.height, threads, threads == 1 ? "" : "s", asked.c_str(), opt.repeat);
    std::printf("structure  %s %s\n", name.c_str(), out["config"].dump().c_str());
    if (out.contains("refit_from"))
        std::printf("refit      the tree built over %s, its boxes refitted: build ms is the refit; SAH cost %.2f\n",
                    out["refit_from"].get<std::string>().c_str(), out["build_stats"]["sah_cost"].get<double>());
    std::printf("%-10s %10s %10s %10s %10s %10s %10s %10s %16s\n", "", "build ms", "(cpu)", "frame ms", "(cpu)",
                "Mrays/s", "(cpu)", "hits", "depth sum");
    auto row = [&](const char* label, const nlohmann::ordered_json& j) {
        std::printf("%-10s %10.1f %10.1f %10.1f %10.1f %10.2f %10.2f %10llu %16.6f\n", label,
                    j["build_ms"].get<double>(), j["build_cpu_ms"].get<double>(), j["frame_ms"].get<double>(),
                    j["frame_cpu_ms"].get<double>(), j["mrays_per_s"].get<double>(), j["mrays_per_cpu_s"].get<double>(),
                    (unsigned long long)j["hit_count"].get<uint64_t>(), j["depth_sum"].get<double>());
    };
    row(name.c_str(), out);
    if (out.contains("gpu")) {
        const auto& g = out["gpu"];
        std::printf("gpu        frame %.1f ms, %.2f Mrays/s (%s); the same triangle as the CPU on %.4f%% of rays, t "
                    "within %.2g relative\n",
                    g["frame_ms"].get<double>(), g["mrays_per_s"].get<double>(), g["device"].get<std::string>().c_str(),
                    100.0 * g["same_triangle_share"].get<double>(), g["max_relative_t"].get<double>());
    }
    const auto& w = out["per_ray"];
    std::printf("per ray    %.2f nodes visited, %.2f box tests, %.2f triangle tests, %.2f mailbox skips\n",
                w["nodes_visited"].get<double>(), w["box_tests"].get<double>(), w["triangle_tests"].get<double>(),
                w["mailbox_skips"].get<double>());
    if (!out.contains("reference")) return;
    const auto& ref = out["reference"];
    std::printf("reference  %s, %s, %s-quality BVH: %s\n", ref["version"].get<std::string>().c_str(),
                ref["call"].get<std::string>().c_str(), ref["build_quality"].get<std::string>().c_str(),
                ref["bvh"].get<std::string>().c_str());
    row("embree", ref);
    std::printf("ratio      speed %.2fx Embree, build %.2fx Embree's time (medians of run-by-run ratios); "
                "same triangle on %.3f%% of pixels\n",
                ref["speed_ratio"].get<double>(), ref["build_ratio"].get<double>(),
                ref["same_triangle_percent"].get<double>());
}

int run_bench(const BenchOptions& opt) {
    auto fail = [](const std::string& message) {
        std::cerr << "accelviz bench: " << message << "\n";
        return 1;
    };
    if (!opt.refit_from.empty() && !opt.reference.empty())
        return fail("--refit-from with --reference: Embree would build while we refit; compare a refit with "
                    "a rebuild by running bench with and without --refit-from");
    if (!opt.reference.empty() && !embree_available())
        return fail("--reference embree: this build has no Embree (CMake did not find embree 3)");
    if (opt.embree_width != 0 && opt.reference != "embree") return fail("--embree-width needs --reference embree");
    if (opt.gpu && (opt.accel.type != AccelType::Bvh || opt.accel.bvh.width != 2))
        return fail("--gpu traverses the binary BVH: use --accel bvh (width 2)");
    if (opt.gpu && opt.accel.triangle_test != TriangleTestKind::MollerTrumbore)
        return fail("--gpu tests triangles by Moller-Trumbore: drop --triangle-test watertight");
    std::string scene = opt.scene;
    if (opt.time) {
        auto at_time = scene_at_time(scene, *opt.time);
        if (!at_time) return fail(at_time.error());
        scene = *at_time;
    }
    auto mesh = load_scene_noting(scene, "bench");
    if (!mesh) return fail(mesh.error());
    std::optional<Mesh> refit_from;  // the scene before it moved: the tree is built over it, then refitted
    if (!opt.refit_from.empty()) {
        if (opt.accel.type != AccelType::Bvh || opt.accel.bvh.width != 2)
            return fail("--refit-from refits the binary BVH: it needs --accel bvh (and --bvh-width 2)");
        auto before = load_scene_noting(opt.refit_from, "bench");
        if (!before) return fail(before.error());
        if (before->indices != mesh->indices)
            return fail("--refit-from " + opt.refit_from + " is not " + scene +
                        " at another time: a refit needs the same triangles (only the vertices may move)");
        refit_from = std::move(*before);
    }
    auto camera_params = opt.camera.resolve(mesh->bounds());
    if (!camera_params) return fail(camera_params.error());
    const std::vector<Ray> rays = camera_rays(Camera(*camera_params, opt.width, opt.height));
    const int threads = effective_threads(opt.threads);  // what runs: 0 and too many ask for all cores
    const std::string name(to_string(opt.accel.type));
    // The builds (oneTBB) get the same threads as the tracing.
    const tbb::global_control build_threads(tbb::global_control::max_allowed_parallelism, size_t(threads));

    // Ours (and the reference, when asked for) build R times, then trace R times. With a
    // reference the two alternate run by run, so a machine that slows down or speeds up
    // over the minutes of a benchmark affects both sides of the ratio alike.
    std::unique_ptr<EmbreeReference> reference;
    if (opt.reference == "embree") reference = std::make_unique<EmbreeReference>(threads, opt.embree_width);
    Measured ours, embree;
    std::shared_ptr<const Accelerator> accel;
    for (int run = 0; run < opt.repeat; ++run) {
        progress("bench: building %s (%d/%d)\n", name, run + 1, opt.repeat);
        accel.reset();  // free the previous one first: one structure in memory at a time (a refit's copy aside)
        Expected<std::shared_ptr<const Accelerator>> built = Error{""};
        if (refit_from) {
            // The update a moving scene pays per frame: the refit alone (the build over
            // the earlier scene is not timed; its tree is refitted in place).
            auto before = build_accelerator(*refit_from, opt.accel);
            if (!before) return fail(before.error());
            Bvh bvh = *structure_if<Bvh>(**before);
            before->reset();
            std::optional<Error> refit_error;
            timed(ours.build_ms, ours.build_cpu_ms, [&] { refit_error = refit_bvh(bvh, *mesh); });
            if (refit_error) return fail(refit_error->message);
            gather_refit_stats(bvh);  // (untimed: the SAH cost and depths of the stretched tree)
            built = std::shared_ptr<const Accelerator>(std::make_shared<AcceleratorFor<Bvh>>(std::move(bvh)));
        } else {
            timed(ours.build_ms, ours.build_cpu_ms, [&] { built = build_accelerator(*mesh, opt.accel); });
        }
        if (!built) return fail(built.error());
        accel = *built;
        if (run == 0) print_memory_budget_note(*accel, "bench");
        if (!reference) continue;
        progress("bench: building %s (%d/%d)\n", "embree", run + 1, opt.repeat);
        std::vector<double> unused_wall;  // Embree times its own build (without the scene set-up)
        timed(unused_wall, embree.build_cpu_ms, [&] { embree.build_ms.push_back(reference->build(*mesh)); });
    }
    ours.results = RayResults(rays.size());
    embree.results = RayResults(reference ? rays.size() : 0);
    for (int run = 0; run < opt.repeat; ++run) {
        progress("bench: tracing with %s (%d/%d)\n", name, run + 1, opt.repeat);
        timed(ours.frame_ms, ours.frame_cpu_ms, [&] {
            for_each_ray_chunk(rays.size(), threads, [&](size_t begin, size_t end) {
                for (size_t i = begin; i < end; ++i) {
                    const Hit hit = accel->intersect_closest(rays[i]);
                    ours.results.t[i] = hit.t;
                    ours.results.tri[i] = hit.tri;
                }
            });
        });
        if (!reference) continue;
        progress("bench: tracing with %s (%d/%d)\n", "embree", run + 1, opt.repeat);
        timed(embree.frame_ms, embree.frame_cpu_ms, [&] { reference->trace(rays, threads, embree.results); });
    }

    nlohmann::ordered_json out;
    out["scene"] = scene;
    out["triangles"] = mesh->triangle_count();
    out["accel"] = accel->name();
    out["config"] = accel->config();
    if (refit_from) out["refit_from"] = opt.refit_from;  // build_ms is then the refit's time
    out["threads"] = threads;
    if (threads != opt.threads) out["threads_requested"] = opt.threads;
    out["width"] = opt.width;
    out["height"] = opt.height;
    out["repeat"] = opt.repeat;
    out["rays"] = rays.size();
    const nlohmann::ordered_json figures = summary(ours, rays.size());  // (items() does not keep a temporary alive)
    for (const auto& [key, value] : figures.items()) out[key] = value;
    out["per_ray"] = work_per_ray(*accel, rays);
    out["build_stats"] = accel->stats();
    if (reference) out["reference"] = reference_json(*reference, embree, ours, rays.size());
    if (opt.gpu) {
        const Bvh* bvh = structure_if<Bvh>(*accel);
        if (!bvh) return fail("--gpu traverses the binary BVH: use --accel bvh (width 2)");
        progress("bench: tracing with %s (%d/%d)\n", "the GPU", opt.repeat, opt.repeat);
        auto gpu = gpu_figures(*bvh, rays, opt.width, opt.height, opt.repeat, ours.results);
        if (!gpu) return fail("--gpu: " + gpu.error());
        out["gpu"] = *gpu;
    }

    if (opt.json)
        std::cout << out.dump(2) << "\n";
    else
        print_table(opt, out, mesh->triangle_count());
    return 0;
}

}  // namespace

Command register_bench(CLI::App& app) {
    auto opt = std::make_shared<BenchOptions>();
    CLI::App* sub = app.add_subcommand("bench", "Time building a structure and tracing one ray per pixel");
    sub->add_option("scene", opt->scene, "OBJ file, or builtin:NAME (e.g. builtin:soup?n=100000)")->required();
    sub->add_option("--width", opt->width, "Image width in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--height", opt->height, "Image height in pixels")->check(whole_number(1, 16384))->capture_default_str();
    sub->add_option("--threads", opt->threads,
                    "Threads for building and tracing (0 = all cores; more than the cores run on all cores, and "
                    "`threads` says how many ran)")
        ->check(whole_number(0, 1024))
        ->capture_default_str();
    sub->add_option("--repeat", opt->repeat, "Runs of build and of trace; the medians are reported")
        ->check(whole_number(1, 1000))
        ->capture_default_str();
    sub->add_flag("--json", opt->json, "One JSON object instead of a table");
    sub->add_option("--reference", opt->reference,
                    std::string("Also run a production ray tracer on the same rays: embree") +
                        (embree_available() ? "" : " (not available: built without Embree)"))
        ->check(CLI::IsMember({"embree"}));
    sub->add_option("--embree-width", opt->embree_width,
                    "With --reference embree: children per node of Embree's BVH, 4 or 8 "
                    "(default: Embree's choice, 8 on a CPU with AVX)")
        ->check(CLI::IsMember({4, 8}));
    sub->add_flag("--gpu", opt->gpu,
                  "Also trace the same rays on the GPU: the binary BVH traversed by an OpenGL 4.3 compute shader "
                  "(headless: llvmpipe); its median frame ms and its agreement with the CPU's answers");
    sub->add_option("--time", opt->time,
                    "A moving scene's time t (builtin:moving, builtin:wave: sets its t=; one period per unit)");
    sub->add_option("--refit-from", opt->refit_from,
                    "bvh: a moving scene's earlier state (the same triangles, e.g. builtin:moving?t=0): build over "
                    "it, then refit the tree's boxes to SCENE; build ms is then the refit's time, and the SAH cost "
                    "and Mrays/s show what the refit tree costs against a rebuild (the same command without it)");
    opt->camera.add_to(*sub);
    add_accel_flags(*sub, opt->accel);
    return {sub, [opt] { return run_bench(*opt); }};
}

}  // namespace accelviz::cli
