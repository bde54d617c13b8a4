#include "core/measure/comparison.h"

#include <algorithm>
#include <chrono>
#include <cmath>

#include <tbb/task_arena.h>

#include "core/traversal/observers.h"
#include "core/util/random.h"

namespace accelviz {

double steady_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::vector<std::pair<std::string, AccelConfig>> comparison_structures() {
    std::vector<std::pair<std::string, AccelConfig>> out;
    auto add = [&](std::string label, AccelType type) {
        AccelConfig config;
        config.type = type;
        out.emplace_back(std::move(label), config);
    };
    add("naive", AccelType::Naive);
    add("grid", AccelType::Grid);
    add("KD tree", AccelType::Kd);
    add("octree", AccelType::Octree);
    add("BVH", AccelType::Bvh);
    return out;
}

namespace {

/// How often a recorded ray met a triangle it had met before (a second
/// TriangleTest of it, or a MailboxSkip).
uint64_t repeats_in(const std::vector<TraversalEvent>& events, std::vector<uint32_t>& met) {
    met.clear();
    for (const TraversalEvent& e : events)
        if (e.kind == EventKind::TriangleTest || e.kind == EventKind::MailboxSkip) met.push_back(e.tri);
    std::sort(met.begin(), met.end());
    return uint64_t(met.size() - size_t(std::unique(met.begin(), met.end()) - met.begin()));
}

}  // namespace

std::vector<Ray> comparison_rays(const Camera& camera, uint64_t count, uint64_t seed) {
    const uint64_t pixels = uint64_t(camera.width()) * uint64_t(camera.height());
    count = std::min(count, pixels);
    std::vector<Ray> rays;
    rays.reserve(count);
    Rng rng(seed);
    for (uint64_t i = 0; i < count; ++i) {
        const uint64_t p = rng.next_u64() % pixels;
        rays.push_back(camera.ray(int(p % uint64_t(camera.width())), int(p / uint64_t(camera.width()))));
    }
    return rays;
}

Expected<StructureComparison> measure_structures(const Mesh& mesh, const Camera& camera,
                                                 const MeasureOptions& options) {
    StructureComparison out;
    out.triangles = mesh.triangle_count();
    out.width = camera.width();
    out.height = camera.height();
    const std::vector<Ray> rays = comparison_rays(camera, options.sample_rays, options.seed);
    out.sample_rays = rays.size();
    const uint64_t naive_rays = std::min<uint64_t>(
        rays.size(), std::max<uint64_t>(16, options.naive_test_budget / std::max<uint64_t>(1, out.triangles)));
    std::vector<Hit> naive_hits;

    // One thread for builds and rays alike: like with like on any machine.
    tbb::task_arena one_thread(1);
    auto structures = comparison_structures();
    structures.insert(structures.end(), options.extra_structures.begin(), options.extra_structures.end());
    for (size_t i = 0; i < structures.size(); ++i) {
        // Named references, not a structured binding: the build's lambda captures them.
        const std::string& label = structures[i].first;
        const AccelConfig& config = structures[i].second;
        if (options.current_row) options.current_row->store(int(i));
        if (cancelled(options.progress)) return WorkProgress::cancelled_error();
        StructureMeasurement row;
        row.label = label;
        row.type = config.type;

        const double build_start = options.clock();
        Expected<std::shared_ptr<const Accelerator>> built =
            one_thread.execute([&] { return build_accelerator(mesh, config, options.progress); });
        row.build_ms = (options.clock() - build_start) * 1e3;
        if (!built) return Error{label + ": " + built.error()};
        const Accelerator& accel = **built;
        if (config.type == AccelType::Naive) row.build_ms = 0;  // nothing was built
        const nlohmann::json stats = accel.stats();
        if (stats.contains("memory_bytes")) row.memory_bytes = stats["memory_bytes"].get<uint64_t>();

        const size_t count = config.type == AccelType::Naive ? size_t(naive_rays) : rays.size();
        row.rays = count;
        if (count == 0) {
            out.rows.push_back(std::move(row));
            continue;
        }
        // The work per ray, and the answers, through the counting path.
        // Only the cell structures put a triangle in several places: they are recorded
        // (to count repeats), the others counted.
        const bool may_repeat =
            config.type == AccelType::Grid || config.type == AccelType::Kd || config.type == AccelType::Octree;
        Counters counters;
        uint64_t repeats = 0;
        RecordingObserver recorder;
        std::vector<uint32_t> met;
        for (size_t r = 0; r < count; ++r) {
            if (r % 64 == 0 && cancelled(options.progress)) return WorkProgress::cancelled_error();
            Hit hit;
            if (may_repeat) {
                recorder.events.clear();
                hit = accel.intersect_closest(rays[r], recorder);
                for (const TraversalEvent& e : recorder.events) counters.add(e);
                repeats += repeats_in(recorder.events, met);
            } else {
                CountingObserver counter;
                hit = accel.intersect_closest(rays[r], counter);
                counters += counter.counters;
            }
            if (config.type == AccelType::Naive) naive_hits.push_back(hit);
            else if (r < naive_hits.size() && (hit.tri != naive_hits[r].tri || hit.t != naive_hits[r].t))
                ++row.mismatches;
        }
        row.nodes_per_ray = double(counters.nodes_visited) / double(count);
        row.triangle_tests_per_ray = double(counters.triangle_tests) / double(count);
        row.repeats_per_ray = double(repeats) / double(count);

        // The time per ray, through the fast path (the one that renders images).
        const double trace_start = options.clock();
        double elapsed = 0;
        uint64_t traced = 0;
        uint32_t sink = 0;
        for (int pass = 0; pass < 64 && (pass == 0 || elapsed < options.min_trace_seconds); ++pass) {
            if (cancelled(options.progress)) return WorkProgress::cancelled_error();
            for (size_t r = 0; r < count; ++r) {
                if (r % 256 == 0 && cancelled(options.progress)) return WorkProgress::cancelled_error();
                sink += accel.intersect_closest(rays[r]).tri;
            }
            traced += count;
            elapsed = options.clock() - trace_start;
        }
        [[maybe_unused]] volatile uint32_t keep = sink;  // the answers are used: the calls stay
        row.ns_per_ray = elapsed * 1e9 / double(traced);
        out.rows.push_back(std::move(row));
    }
    return out;
}

// [SECTION] Amortization

std::optional<double> break_even_rays(const StructureMeasurement& baseline, const StructureMeasurement& row) {
    const double saved_per_ray_ms = (baseline.ns_per_ray - row.ns_per_ray) * 1e-6;
    if (!(saved_per_ray_ms > 0)) return std::nullopt;
    return std::max(0.0, (row.build_ms - baseline.build_ms) / saved_per_ray_ms);
}

AmortizationChart amortization_chart(const StructureComparison& comparison, double max_rays, int points) {
    AmortizationChart chart;
    chart.max_rays = std::max(1.0, max_rays);
    points = std::max(points, 2);
    for (const StructureMeasurement& row : comparison.rows) {
        AmortizationChart::Series series;
        series.label = row.label;
        for (int i = 0; i < points; ++i) {
            const double rays = std::pow(chart.max_rays, double(i) / double(points - 1));  // 1 .. max_rays
            series.rays.push_back(rays);
            series.total_ms.push_back(row.total_ms(rays));
        }
        chart.series.push_back(std::move(series));
    }
    if (comparison.rows.empty()) return chart;
    for (size_t i = 1; i < comparison.rows.size(); ++i) {
        const auto rays = break_even_rays(comparison.rows[0], comparison.rows[i]);
        if (rays && *rays <= chart.max_rays)
            chart.break_even.push_back({i, *rays, comparison.rows[i].total_ms(*rays)});
    }
    return chart;
}

}  // namespace accelviz
