#include "core/measure/scaling.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "core/accel/memory_budget.h"
#include "core/geometry/scene.h"
#include "core/render/rasterizer.h"
#include "core/render/ray_caster.h"

namespace accelviz {

namespace {

double ms_between(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
    return std::chrono::duration<double, std::milli>(b - a).count();
}

/// The median of `repeat` runs of f (each returning its milliseconds; for an even
/// count the upper of the middle two). Stops early once `progress` is cancelled.
template <class F>
double median_ms(int repeat, const WorkProgress* progress, F&& f) {
    std::vector<double> runs;
    for (int i = 0; i < std::max(1, repeat) && (i == 0 || !cancelled(progress)); ++i) runs.push_back(f());
    std::sort(runs.begin(), runs.end());
    return runs[runs.size() / 2];
}

/// "1.1M", "277k", "69451": a triangle count for step names.
std::string short_count(uint64_t n) {
    char text[32];
    if (n >= 1'000'000) std::snprintf(text, sizeof text, "%.1fM", double(n) / 1e6);
    else if (n >= 10'000) std::snprintf(text, sizeof text, "%.0fk", double(n) / 1e3);
    else std::snprintf(text, sizeof text, "%llu", (unsigned long long)n);
    return text;
}

std::string structure_name(const AccelConfig& c) {
    std::string name(to_string(c.type));
    if (c.type == AccelType::Bvh && c.bvh.width != 2) name += " " + std::to_string(c.bvh.width) + "-wide";
    return name;
}

}  // namespace

std::vector<uint64_t> scaling_copies(uint64_t triangles, uint64_t max_triangles) {
    std::vector<uint64_t> copies = {1};
    while (triangles > 0 && copies.size() < kScalingMaxScenes && 2 * copies.back() * triangles <= max_triangles)
        copies.push_back(2 * copies.back());
    return copies;
}

std::pair<uint64_t, uint64_t> scaling_grid(uint64_t copies) {
    uint64_t nx = 1, nz = 1;
    while (nx * nz < copies) (nx == nz ? nx : nz) *= 2;
    return {nx, nz};
}

Expected<ScalingResult> measure_scaling(const Mesh& one, const ScalingOptions& options) {
    if (one.triangle_count() == 0) return Error{"the scaling chart needs a mesh with triangles"};
    if (options.structures.empty()) return Error{"the scaling chart needs at least one structure"};
    if (options.width < 1 || options.height < 1) return Error{"the scaling chart's frames need a size"};
    for (const AccelConfig& c : options.structures) {
        if (c.type == AccelType::Naive)
            return Error{"the scaling chart does not ray cast through naive: every triangle for every ray"};
        if (auto err = validate(c)) return *err;
    }
    ScalingResult result;
    result.mesh_name = one.name;
    result.mesh_triangles = one.triangle_count();
    result.structures = options.structures;
    result.width = options.width;
    result.height = options.height;
    result.threads = effective_threads(options.threads);
    const auto step = [&](const std::string& text) {
        if (options.on_step) options.on_step(text);
    };
    using clock = std::chrono::steady_clock;
    for (const uint64_t copies : scaling_copies(one.triangle_count(), options.max_triangles)) {
        if (cancelled(options.progress)) return WorkProgress::cancelled_error();
        const auto [nx, nz] = scaling_grid(copies);
        const std::string scene_name =
            std::to_string(copies) + (copies == 1 ? " copy, " : " copies, ") +
            short_count(copies * one.triangle_count()) + " triangles";
        // The scene, its triangle array and OpenGL's copy: refused beyond the memory budget.
        const double scene_bytes = 3.0 * double(copies) * double(one.positions.size() * sizeof(Vec3) +
                                                                 one.indices.size() * sizeof(one.indices[0]));
        if (copies > 1 && scene_bytes > double(default_memory_budget())) {
            result.stopped_early = "stopped before " + scene_name + ": it would need about " +
                                   std::to_string(uint64_t(scene_bytes / 1e6)) + " MB, over the memory budget";
            return result;
        }
        step(scene_name + ": making the scene");
        auto mesh = repeat_on_grid(one, nx, nz, options.progress);
        if (!mesh) {
            if (cancelled(options.progress) || result.points.empty()) return Error{mesh.error()};
            result.stopped_early = "stopped before " + scene_name + ": " + mesh.error();
            return result;
        }
        const Camera camera(default_camera(mesh->bounds()), options.width, options.height);
        ScalingPoint point;
        point.copies = copies;
        point.triangles = mesh->triangle_count();

        // One structure at a time: built, its frames cast, and freed before the next is
        // built (a few structures over 20M triangles would not fit together). One that
        // does not fit the memory budget ends the series here.
        for (const AccelConfig& config : options.structures) {
            step(scene_name + ": building " + structure_name(config));
            const auto start = clock::now();
            auto accel = build_accelerator(*mesh, config, options.progress);
            if (!accel) {
                if (cancelled(options.progress)) return WorkProgress::cancelled_error();
                if (result.points.empty()) return Error{accel.error()};
                result.stopped_early = "stopped before " + scene_name + ": " + accel.error();
                return result;
            }
            point.build_ms.push_back(ms_between(start, clock::now()));
            step(scene_name + ": ray casting through " + structure_name(config));
            const RayCastOptions cast_options{.threads = options.threads, .cancel = options.progress};
            ray_cast(**accel, *mesh, camera, cast_options);  // not timed: caches and pages warm
            point.cast_ms.push_back(median_ms(options.repeat, options.progress, [&] {
                const auto start_cast = clock::now();
                ray_cast(**accel, *mesh, camera, cast_options);
                return ms_between(start_cast, clock::now());
            }));
            if (cancelled(options.progress)) return WorkProgress::cancelled_error();
        }
        if (cancelled(options.progress)) return WorkProgress::cancelled_error();
        step(scene_name + ": rasterizing (CPU z-buffer)");
        point.cpu_raster_ms = median_ms(options.repeat, options.progress, [&] {
            const auto start = clock::now();
            rasterize(*mesh, camera);
            return ms_between(start, clock::now());
        });
        if (options.gl_raster_ms) {
            step(scene_name + ": rasterizing (OpenGL)");
            const auto gl_error = [&](const std::string& error) {
                return cancelled(options.progress) ? WorkProgress::cancelled_error() : Error{"OpenGL: " + error};
            };
            auto warm = options.gl_raster_ms(*mesh, camera);
            if (!warm) return gl_error(warm.error());
            std::vector<double> runs;
            for (int i = 0; i < std::max(1, options.repeat); ++i) {
                auto ms = options.gl_raster_ms(*mesh, camera);
                if (!ms) return gl_error(ms.error());
                runs.push_back(*ms);
            }
            std::sort(runs.begin(), runs.end());
            point.gl_raster_ms = runs[runs.size() / 2];
        }
        if (cancelled(options.progress)) return WorkProgress::cancelled_error();
        result.points.push_back(std::move(point));
    }
    return result;
}

LineChart scaling_chart(const ScalingResult& r) {
    LineChart chart;
    const std::string name = r.mesh_name.substr(r.mesh_name.find_last_of('/') + 1);  // a path's file name
    chart.title = "Frame time against triangles: " + name + " repeated";
    chart.x_label = "triangles";
    std::ostringstream y_label;
    y_label << "ms per frame (" << r.width << "x" << r.height << ", ray casts on " << r.threads
            << (r.threads == 1 ? " thread)" : " threads)");
    chart.y_label = y_label.str();
    chart.log_log = true;
    static const Rgb kCast[] = {{40, 110, 200}, {30, 150, 90}, {150, 80, 190}, {20, 160, 170}, {120, 120, 40}};
    const auto add = [&](const std::string& name, Rgb colour, auto&& value) {
        ChartSeries s{name, colour, {}, {}};
        for (const ScalingPoint& p : r.points)
            if (const std::optional<double> y = value(p)) {
                s.x.push_back(double(p.triangles));
                s.y.push_back(*y);
            }
        if (!s.x.empty()) chart.series.push_back(std::move(s));
    };
    add("raster: OpenGL", {205, 70, 50}, [](const ScalingPoint& p) { return p.gl_raster_ms; });
    add("raster: CPU", {225, 140, 40}, [](const ScalingPoint& p) { return std::optional<double>(p.cpu_raster_ms); });
    for (size_t k = 0; k < r.structures.size(); ++k)
        add("ray cast: " + structure_name(r.structures[k]), kCast[k % std::size(kCast)], [k](const ScalingPoint& p) {
            return k < p.cast_ms.size() ? std::optional<double>(p.cast_ms[k]) : std::nullopt;
        });
    return chart;
}

std::string scaling_table(const ScalingResult& r) {
    std::ostringstream out;
    char cell[64];
    const bool gl = std::any_of(r.points.begin(), r.points.end(), [](const ScalingPoint& p) { return p.gl_raster_ms; });
    out << r.mesh_name << " (" << r.mesh_triangles << " triangles) repeated; frames " << r.width << "x" << r.height
        << ", ray casts on " << r.threads << (r.threads == 1 ? " thread" : " threads")
        << ", the CPU rasterizer on one" << (r.gl_renderer.empty() ? "" : ", OpenGL: " + r.gl_renderer) << "\n\n";
    out << "| copies | triangles | raster CPU ms |" << (gl ? " raster OpenGL ms |" : "");
    for (const AccelConfig& c : r.structures)
        out << " " << structure_name(c) << " build ms | " << structure_name(c) << " ray cast ms |";
    out << "\n|---:|---:|---:|" << (gl ? "---:|" : "");
    for (size_t k = 0; k < r.structures.size(); ++k) out << "---:|---:|";
    out << "\n";
    for (const ScalingPoint& p : r.points) {
        out << "| " << p.copies << " | " << p.triangles << " |";
        std::snprintf(cell, sizeof cell, " %.1f |", p.cpu_raster_ms);
        out << cell;
        if (gl) {
            if (p.gl_raster_ms) std::snprintf(cell, sizeof cell, " %.1f |", *p.gl_raster_ms);
            else std::snprintf(cell, sizeof cell, " |");
            out << cell;
        }
        for (size_t k = 0; k < p.cast_ms.size(); ++k) {
            std::snprintf(cell, sizeof cell, " %.1f | %.1f |", p.build_ms[k], p.cast_ms[k]);
            out << cell;
        }
        out << "\n";
    }
    if (!r.stopped_early.empty()) out << "\n" << r.stopped_early << "\n";
    return out.str();
}

}  // namespace accelviz
