// The measured comparison table and the amortization chart: the counts against
// the structures' own counters, the answers against naive, the timing arithmetic
// on a clock the test controls, and the chart against the numbers it plots.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "core/exchange/structure_file.h"
#include "core/geometry/scene.h"
#include "core/measure/comparison.h"
#include "core/traversal/observers.h"

using namespace accelviz;

namespace {

/// A clock that moves one millisecond each time it is read.
MeasureClock ticking_clock() {
    auto now = std::make_shared<double>(0.0);
    return [now] { return *now += 1e-3; };
}

MeasureOptions small_options(uint64_t rays = 300) {
    MeasureOptions options;
    options.sample_rays = rays;
    options.clock = ticking_clock();
    return options;
}

const Mesh& teapot() {
    static const Mesh mesh = *load_scene("builtin:teapot?n=4");
    return mesh;
}

}  // namespace

TEST(Comparison, RowsAreTheLecturesStructuresWithNaiveFirst) {
    const Camera camera(default_camera(teapot().bounds()), 64, 48);
    auto measured = measure_structures(teapot(), camera, small_options());
    ASSERT_TRUE(measured) << measured.error();
    std::vector<AccelType> types;
    for (const auto& row : measured->rows) types.push_back(row.type);
    EXPECT_EQ(types, (std::vector<AccelType>{AccelType::Naive, AccelType::Grid, AccelType::Kd, AccelType::Octree,
                                              AccelType::Bvh}));
    EXPECT_EQ(measured->triangles, teapot().triangle_count());
    EXPECT_EQ(measured->sample_rays, 300u);
}

TEST(Comparison, CountsAreTheStructuresOwnCountersOverTheSameRays) {
    const Mesh& mesh = teapot();
    const Camera camera(default_camera(mesh.bounds()), 64, 48);
    const MeasureOptions options = small_options();
    auto measured = measure_structures(mesh, camera, options);
    ASSERT_TRUE(measured) << measured.error();
    const std::vector<Ray> rays = comparison_rays(camera, options.sample_rays, options.seed);
    ASSERT_EQ(rays.size(), 300u);
    const auto structures = comparison_structures();
    for (size_t i = 0; i < structures.size(); ++i) {
        SCOPED_TRACE(structures[i].first);
        const StructureMeasurement& row = measured->rows[i];
        auto accel = build_accelerator(mesh, structures[i].second);
        ASSERT_TRUE(accel) << accel.error();
        // The repeats counted the slow, plain way: each triangle met, and met again.
        Counters sum;
        uint64_t repeats = 0;
        for (size_t r = 0; r < row.rays; ++r) {
            RecordingObserver recorder;
            (*accel)->intersect_closest(rays[r], recorder);
            sum += recorder.counters();
            std::vector<uint32_t> met;
            for (const TraversalEvent& e : recorder.events)
                if (e.kind == EventKind::TriangleTest || e.kind == EventKind::MailboxSkip) {
                    if (std::find(met.begin(), met.end(), e.tri) != met.end()) ++repeats;
                    met.push_back(e.tri);
                }
        }
        const double n = double(row.rays);
        EXPECT_DOUBLE_EQ(row.nodes_per_ray, double(sum.nodes_visited) / n);
        EXPECT_DOUBLE_EQ(row.triangle_tests_per_ray, double(sum.triangle_tests) / n);
        EXPECT_DOUBLE_EQ(row.repeats_per_ray, double(repeats) / n);
        EXPECT_EQ(row.mismatches, 0u);
    }
    // Naive tests every triangle once per ray; the BVH never meets one twice; the
    // grid, with triangles in several cells, does.
    EXPECT_DOUBLE_EQ(measured->rows[0].triangle_tests_per_ray, double(mesh.triangle_count()));
    EXPECT_EQ(measured->rows[0].repeats_per_ray, 0.0);
    EXPECT_EQ(measured->rows[4].repeats_per_ray, 0.0);
    EXPECT_GT(measured->rows[1].repeats_per_ray, 0.0);
    EXPECT_LT(measured->rows[4].triangle_tests_per_ray, measured->rows[0].triangle_tests_per_ray / 10);
}

TEST(Comparison, NaiveTracesOnlyWhatItsBudgetAllows) {
    MeasureOptions options = small_options(1000);
    options.naive_test_budget = 100 * teapot().triangle_count();
    const Camera camera(default_camera(teapot().bounds()), 64, 48);
    auto measured = measure_structures(teapot(), camera, options);
    ASSERT_TRUE(measured) << measured.error();
    EXPECT_EQ(measured->rows[0].rays, 100u);
    for (size_t i = 1; i < measured->rows.size(); ++i) EXPECT_EQ(measured->rows[i].rays, 1000u);
}

TEST(Comparison, TimesComeFromTheClockBuildsAndRaysApart) {
    // The clock moves 1 ms per read: every build reads it twice (1 ms), and the rays
    // are traced again until 50 ms have passed: 50 passes of the sample, 1 ms each.
    const Camera camera(default_camera(teapot().bounds()), 64, 48);
    auto measured = measure_structures(teapot(), camera, small_options(200));
    ASSERT_TRUE(measured) << measured.error();
    EXPECT_EQ(measured->rows[0].build_ms, 0.0);  // naive builds nothing
    for (const StructureMeasurement& row : measured->rows) {
        SCOPED_TRACE(row.label);
        if (row.type != AccelType::Naive) {
            EXPECT_NEAR(row.build_ms, 1.0, 1e-6);
            EXPECT_GT(row.memory_bytes, 0u);
        }
        EXPECT_NEAR(row.ns_per_ray, 1e6 / double(row.rays), 1e-3);
        EXPECT_NEAR(row.mrays_per_second(), 1e3 / row.ns_per_ray, 1e-9);
    }
}

TEST(Comparison, ACancelledMeasurementSaysSo) {
    WorkProgress progress;
    progress.cancel();
    MeasureOptions options = small_options();
    options.progress = &progress;
    const Camera camera(default_camera(teapot().bounds()), 64, 48);
    auto measured = measure_structures(teapot(), camera, options);
    ASSERT_FALSE(measured);
    EXPECT_EQ(measured.error(), "cancelled");
}

TEST(Comparison, AnEmptySceneMeasuresWithoutDividingByZero) {
    const Mesh empty;
    const Camera camera(CameraParams{}, 8, 8);
    auto measured = measure_structures(empty, camera, small_options(16));
    ASSERT_TRUE(measured) << measured.error();
    for (const StructureMeasurement& row : measured->rows) {
        EXPECT_EQ(row.triangle_tests_per_ray, 0.0) << row.label;
        EXPECT_EQ(row.mismatches, 0u) << row.label;
    }
}

// [SECTION] Amortization

namespace {
StructureMeasurement row_of(const char* label, double build_ms, double ns_per_ray) {
    StructureMeasurement row;
    row.label = label;
    row.build_ms = build_ms;
    row.ns_per_ray = ns_per_ray;
    return row;
}
}  // namespace

TEST(Amortization, BreakEvenIsWhereTheTotalsMeet) {
    const auto naive = row_of("naive", 0, 1000);
    // 3 ms to build, 900 ns saved per ray: 3 / 0.0009 = 3333.3 rays.
    const auto bvh = row_of("BVH", 3, 100);
    ASSERT_TRUE(break_even_rays(naive, bvh));
    EXPECT_NEAR(*break_even_rays(naive, bvh), 3333.333, 1e-3);
    EXPECT_NEAR(naive.total_ms(3333.333333), bvh.total_ms(3333.333333), 1e-6);
    // Slower per ray: never pays off. Cheaper to build and faster: ahead at once.
    EXPECT_FALSE(break_even_rays(naive, row_of("slow", 1, 2000)));
    EXPECT_FALSE(break_even_rays(naive, row_of("same", 1, 1000)));
    EXPECT_EQ(*break_even_rays(row_of("dear", 5, 1000), row_of("cheap", 1, 100)), 0.0);
}

TEST(Amortization, TheChartPlotsBuildPlusRaysTimesTimePerRay) {
    StructureComparison comparison;
    comparison.rows = {row_of("naive", 0, 1000), row_of("grid", 2, 300), row_of("BVH", 3, 100),
                       row_of("slow", 50, 2000), row_of("late", 1000, 999)};
    const AmortizationChart chart = amortization_chart(comparison, 1e6, 16);
    ASSERT_EQ(chart.series.size(), 5u);
    for (size_t s = 0; s < chart.series.size(); ++s) {
        const auto& series = chart.series[s];
        ASSERT_EQ(series.rays.size(), 16u);
        EXPECT_DOUBLE_EQ(series.rays.front(), 1.0);
        EXPECT_NEAR(series.rays.back(), 1e6, 1e-6);
        for (size_t i = 0; i < series.rays.size(); ++i) {
            if (i > 0) {
                EXPECT_GT(series.rays[i], series.rays[i - 1]);
            }
            EXPECT_DOUBLE_EQ(series.total_ms[i], comparison.rows[s].total_ms(series.rays[i]));
        }
    }
    // grid and BVH pay off within a million rays; "slow" never; "late" after 1e9 rays.
    ASSERT_EQ(chart.break_even.size(), 2u);
    EXPECT_EQ(chart.break_even[0].row, 1u);
    EXPECT_NEAR(chart.break_even[0].rays, 2.0 / 0.0007, 1e-6);
    EXPECT_EQ(chart.break_even[1].row, 2u);
    for (const auto& point : chart.break_even)
        EXPECT_NEAR(point.total_ms, comparison.rows[0].total_ms(point.rays), 1e-9);
}

TEST(Comparison, AStructureFromAFileIsMeasuredAfterOursAndExact) {
    // Our KD tree written out as a student's tool would, then measured as an extra row.
    const Mesh& mesh = teapot();
    AccelConfig kd;
    kd.type = AccelType::Kd;
    auto built = build_accelerator(mesh, kd);
    ASSERT_TRUE(built);
    auto file = export_structure(**built, mesh, {"builtin:teapot?n=4", 0, std::nullopt});
    ASSERT_TRUE(file);
    const std::string path = ::testing::TempDir() + "comparison_kd.json";
    ASSERT_FALSE(write_structure_file(*file, path).has_value());
    MeasureOptions options = small_options();
    AccelConfig from_file;
    from_file.type = AccelType::Kd;
    from_file.structure_file = path;
    options.extra_structures = {{"file's tree", from_file}};
    const Camera camera(default_camera(mesh.bounds()), 64, 48);
    auto measured = measure_structures(mesh, camera, options);
    ASSERT_TRUE(measured) << measured.error();
    ASSERT_EQ(measured->rows.size(), 6u);
    const StructureMeasurement& ours = measured->rows[2];
    const StructureMeasurement& theirs = measured->rows[5];
    EXPECT_EQ(theirs.label, "file's tree");
    EXPECT_EQ(theirs.mismatches, 0u);
    EXPECT_EQ(theirs.nodes_per_ray, ours.nodes_per_ray) << "the same tree, the same walk";
    EXPECT_EQ(theirs.triangle_tests_per_ray, ours.triangle_tests_per_ray);
    EXPECT_EQ(theirs.repeats_per_ray, ours.repeats_per_ray);
}
