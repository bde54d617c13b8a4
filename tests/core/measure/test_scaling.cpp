// The scaling chart's measurement: the scenes it makes, what it measures on each,
// and where it stops.
#include <gtest/gtest.h>

#include "core/geometry/scene.h"
#include "core/measure/scaling.h"

using namespace accelviz;

TEST(Scaling, CopiesDoubleWhileTheyFitAndLieOnAGrid) {
    EXPECT_EQ(scaling_copies(1000, 8000), (std::vector<uint64_t>{1, 2, 4, 8}));
    EXPECT_EQ(scaling_copies(1000, 7999), (std::vector<uint64_t>{1, 2, 4}));
    EXPECT_EQ(scaling_copies(1000, 10), (std::vector<uint64_t>{1})) << "one copy even over the limit";
    EXPECT_EQ(scaling_grid(1), (std::pair<uint64_t, uint64_t>{1, 1}));
    EXPECT_EQ(scaling_grid(2), (std::pair<uint64_t, uint64_t>{2, 1}));
    EXPECT_EQ(scaling_grid(8), (std::pair<uint64_t, uint64_t>{4, 2}));
    EXPECT_EQ(scaling_grid(64), (std::pair<uint64_t, uint64_t>{8, 8}));
}

TEST(Scaling, EveryScenesFramesAreMeasuredThroughEveryStructure) {
    auto one = load_scene("builtin:teapot?n=4");
    ASSERT_TRUE(one.ok());
    const uint64_t n = one->triangle_count();
    ScalingOptions options;
    AccelConfig grid;
    grid.type = AccelType::Grid;
    options.structures = {bvh_config_default(), grid};
    options.max_triangles = 4 * n;
    options.width = 64;
    options.height = 36;
    options.repeat = 2;
    std::vector<size_t> gl_calls;  // the triangles of each mesh OpenGL was asked to draw
    options.gl_raster_ms = [&](const Mesh& mesh, const Camera& camera) -> Expected<double> {
        EXPECT_EQ(camera.width(), 64);
        gl_calls.push_back(mesh.triangle_count());
        return 1.0 + double(gl_calls.size());
    };
    std::vector<std::string> steps;
    options.on_step = [&](const std::string& step) { steps.push_back(step); };
    auto result = measure_scaling(*one, options);
    ASSERT_TRUE(result.ok()) << result.error();
    ASSERT_EQ(result->points.size(), 3u);
    EXPECT_TRUE(result->stopped_early.empty());
    for (size_t i = 0; i < 3; ++i) {
        const ScalingPoint& p = result->points[i];
        EXPECT_EQ(p.copies, uint64_t(1) << i);
        EXPECT_EQ(p.triangles, p.copies * n);
        EXPECT_GT(p.cpu_raster_ms, 0);
        ASSERT_EQ(p.build_ms.size(), 2u);
        ASSERT_EQ(p.cast_ms.size(), 2u);
        EXPECT_GT(p.cast_ms[0], 0);
        EXPECT_GT(p.cast_ms[1], 0);
        // One frame not timed, then two: the median of the two OpenGL figures.
        ASSERT_TRUE(p.gl_raster_ms.has_value());
        EXPECT_EQ(*p.gl_raster_ms, 1.0 + double(3 * i + 3));
    }
    EXPECT_EQ(gl_calls, (std::vector<size_t>{n, n, n, 2 * n, 2 * n, 2 * n, 4 * n, 4 * n, 4 * n}));
    EXPECT_EQ(steps.front(), "1 copy, " + std::to_string(n) + " triangles: making the scene");
    // The chart: both rasters and both ray casts; the table: a row per scene.
    const LineChart chart = scaling_chart(*result);
    ASSERT_EQ(chart.series.size(), 4u);
    EXPECT_EQ(chart.series[2].name, "ray cast: bvh");
    EXPECT_EQ(chart.series[3].name, "ray cast: grid");
    EXPECT_EQ(chart.series[3].x, (std::vector<double>{double(n), double(2 * n), double(4 * n)}));
    const std::string table = scaling_table(*result);
    EXPECT_NE(table.find("| 4 | " + std::to_string(4 * n) + " |"), std::string::npos) << table;
}

TEST(Scaling, AStructureOverTheMemoryBudgetEndsTheSeriesThere) {
    auto one = load_scene("builtin:teapot?n=4");
    ASSERT_TRUE(one.ok());
    ScalingOptions options;
    AccelConfig grid;
    grid.type = AccelType::Grid;
    grid.grid.density = 1000;  // cells: 1000 per triangle
    grid.memory_budget = uint64_t(60) << 20;
    options.structures = {grid};
    options.max_triangles = 64 * one->triangle_count();
    options.width = 32;
    options.height = 18;
    options.repeat = 1;
    auto result = measure_scaling(*one, options);
    ASSERT_TRUE(result.ok()) << result.error();
    EXPECT_GE(result->points.size(), 1u);
    EXPECT_LT(result->points.size(), 7u);
    EXPECT_NE(result->stopped_early.find("stopped before"), std::string::npos) << result->stopped_early;
    // The first scene's structure not fitting is an error, not an empty chart.
    options.max_triangles = 1;
    grid.memory_budget = 1 << 10;
    options.structures = {grid};
    EXPECT_FALSE(measure_scaling(*one, options).ok());
}

TEST(Scaling, AnEmptyMeshIsAnError) {
    EXPECT_FALSE(measure_scaling(Mesh{}, ScalingOptions{}).ok());
}
