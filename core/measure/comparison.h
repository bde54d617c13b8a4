#pragma once
/// The lecture's comparison table (grid / KD tree / BVH: "which is best?"),
/// filled with numbers measured on this machine for the current scene and camera,
/// and the chart that follows from it: total time = build + rays x time per ray,
/// against the number of rays. A structure that costs more to build pays for
/// itself after some number of rays (its break-even point against naive); the
/// chart marks where.
///
/// Everything is measured on one thread, builds included, so the rows compare
/// like with like on any machine. Rays are a seeded sample of the camera's
/// pixels (most of a real frame may miss the mesh, and the sample keeps them).

#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/accel/factory.h"
#include "core/geometry/mesh.h"
#include "core/render/camera.h"
#include "core/util/expected.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// One structure's row, measured.
struct StructureMeasurement {
    std::string label;  ///< "naive", "grid", "KD tree", "octree", "BVH"
    AccelType type = AccelType::Naive;
    double build_ms = 0;          ///< build_accelerator on one thread (0 for naive)
    uint64_t memory_bytes = 0;    ///< the structure's own arrays (its stats' memory_bytes; 0 for naive)
    uint64_t rays = 0;            ///< rays traced for the figures below (naive: a prefix of the sample)
    double ns_per_ray = 0;        ///< closest hit, fast path, one thread
    double nodes_per_ray = 0;     ///< nodes (or cells) visited
    double triangle_tests_per_ray = 0;
    /// Times a ray met a triangle it had met before in another cell or node: tested
    /// again, or skipped by the mailbox. 0 for naive and the BVH (a triangle is in
    /// one leaf); the price of putting a triangle in several cells.
    double repeats_per_ray = 0;
    /// Rays (of those naive traced) whose closest hit differs from naive's; 0 when exact.
    uint64_t mismatches = 0;

    double mrays_per_second() const { return ns_per_ray > 0 ? 1e3 / ns_per_ray : 0; }
    /// Build plus `rays` rays, in milliseconds.
    double total_ms(double rays) const { return build_ms + rays * ns_per_ray * 1e-6; }
};

struct StructureComparison {
    uint64_t triangles = 0;
    int width = 0, height = 0;  ///< the image whose pixels the rays sample
    uint64_t sample_rays = 0;   ///< rays per structure (naive may trace fewer)
    std::vector<StructureMeasurement> rows;  ///< naive first
};

/// Seconds on some clock (measurements use differences only).
using MeasureClock = std::function<double()>;
/// std::chrono::steady_clock.
double steady_seconds();

struct MeasureOptions {
    uint64_t sample_rays = 4096;  ///< pixels sampled from the image (seeded; at most width x height)
    uint64_t seed = 1;
    /// Naive traces only as many of the sample as keep its triangle tests under this
    /// (at least 16 rays): it tests every triangle for every ray.
    uint64_t naive_test_budget = 100'000'000;
    /// Each structure's sample is traced again until this much time has passed
    /// (at least once, at most 64 times): a fast structure's figure then rests on
    /// more than a few milliseconds.
    double min_trace_seconds = 0.05;
    MeasureClock clock = steady_seconds;
    /// Hears each build's progress (a stage per structure) and may cancel.
    WorkProgress* progress = nullptr;
    /// Set to the row being measured (0-based), for a progress label.
    std::atomic<int>* current_row = nullptr;
    /// Measured after ours, in this order: e.g. a structure from a file (a student's
    /// tree, AccelConfig::structure_file), whose "build" is reading and checking it.
    std::vector<std::pair<std::string, AccelConfig>> extra_structures;
};

/// The rays measured: `count` pixels of `camera`'s image drawn with Rng(seed)
/// (repeats possible), at most width x height of them.
std::vector<Ray> comparison_rays(const Camera& camera, uint64_t count, uint64_t seed);

/// The structures measured, in the table's order: naive, grid, KD tree, octree,
/// BVH, each with its defaults.
std::vector<std::pair<std::string, AccelConfig>> comparison_structures();

/// Builds every structure of comparison_structures() over `mesh` and traces the
/// same sample of `camera`'s pixels through each. Errors: a build's (naming the
/// structure), or WorkProgress::cancelled_error().
Expected<StructureComparison> measure_structures(const Mesh& mesh, const Camera& camera,
                                                 const MeasureOptions& options = {});

// [SECTION] Amortization

/// Where structure `row`'s total time line crosses `baseline`'s: the number of rays
/// after which building it has paid for itself,
///   rays* = (build_row - build_base) / (per_ray_base - per_ray_row),
/// 0 when it is ahead from the first ray (no dearer to build, and faster per ray),
/// nothing when it never pays off (not faster per ray than the baseline).
std::optional<double> break_even_rays(const StructureMeasurement& baseline, const StructureMeasurement& row);

/// The chart's data: each row's total time at log-spaced ray counts from 1 to
/// `max_rays`, and each row's break-even point against naive (rows[0]).
struct AmortizationChart {
    struct Series {
        std::string label;
        std::vector<double> rays, total_ms;
    };
    struct BreakEven {
        size_t row = 0;  ///< index into the comparison's rows
        double rays = 0, total_ms = 0;
    };
    std::vector<Series> series;
    std::vector<BreakEven> break_even;  ///< against naive, for the rows that pay off within max_rays
    double max_rays = 0;
};
AmortizationChart amortization_chart(const StructureComparison& comparison, double max_rays, int points = 64);

}  // namespace accelviz
