// The memory budget: sizes as --memory-budget reads them, builds that cannot fit
// refused with the flag to change, and trees whose references are capped to fit
// still exact against brute force.
#include <gtest/gtest.h>

#include "accel/space_partition_support.h"
#include "core/accel/memory_budget.h"

using namespace accelviz;
using namespace accelviz::test;

namespace {

TEST(MemoryBudget, SizesReadAsAPersonWritesThem) {
    EXPECT_EQ(parse_memory_size("4G"), uint64_t(4) << 30);
    EXPECT_EQ(parse_memory_size("512M"), uint64_t(512) << 20);
    EXPECT_EQ(parse_memory_size("64k"), uint64_t(64) << 10);
    EXPECT_EQ(parse_memory_size("1.5G"), uint64_t(3) << 29);
    EXPECT_EQ(parse_memory_size("65536"), uint64_t(65536));
    for (const char* bad : {"", "G", "-1G", "0", "0.1", "12Q", "1e30G", "nanG", "4 G", "inf"})
        EXPECT_FALSE(parse_memory_size(bad)) << bad;
    EXPECT_GT(default_memory_budget(), uint64_t(0));
}

TEST(MemoryBudget, ABuildThatCannotFitIsRefusedNamingTheFlag) {
    const SceneCase& scene = scene_case("builtin:soup?n=5000", 8);
    for (AccelType type :
         {AccelType::Naive, AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree, AccelType::Bsp}) {
        AccelConfig config;
        config.type = type;
        config.memory_budget = 64 * 1024;  // under what even one reference per triangle takes
        const auto built = build_accelerator(scene.mesh, config);
        ASSERT_FALSE(built) << to_string(type);
        EXPECT_NE(built.error().find("--memory-budget"), std::string::npos) << built.error();
        EXPECT_NE(built.error().find("5000 triangles"), std::string::npos) << built.error();
        EXPECT_NE(built.error().find("64 KB"), std::string::npos) << built.error();
    }
    AccelConfig grid;
    grid.type = AccelType::Grid;
    grid.grid.density = 1000;  // 5M cells: 20 MB of list starts
    grid.memory_budget = 8 << 20;
    const auto built = build_accelerator(scene.mesh, grid);
    ASSERT_FALSE(built);
    EXPECT_NE(built.error().find("--grid-density"), std::string::npos) << built.error();
}

TEST(MemoryBudget, TheEstimateIsAnUpperBoundOfWhatTheStructureHolds) {
    // The structure's own arrays (memory_bytes) are part of what the estimate
    // covers; the build's scratch is the rest.
    const SceneCase& scene = scene_case("builtin:soup?n=20000", 8);
    for (AccelType type : {AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree, AccelType::Bsp}) {
        AccelConfig config;
        config.type = type;
        const auto built = build_accelerator(scene.mesh, config);
        ASSERT_TRUE(built) << built.error();
        const auto stats = (*built)->stats();
        const uint64_t holds = stats["memory_bytes"].get<uint64_t>();
        const uint64_t references = stats.contains("references") ? stats["references"].get<uint64_t>() : 0;
        const uint64_t estimate = fixed_build_bytes(config, 20000) + bytes_per_reference(config) * references;
        EXPECT_LE(holds, estimate) << to_string(type);
    }
}

TEST(MemoryBudget, CappedTreesStayExactAndSaySo) {
    const SceneCase& scene = scene_case("builtin:teapot?n=8");
    const uint64_t n = scene.mesh.triangle_count();
    for (AccelType type : {AccelType::Kd, AccelType::Octree, AccelType::Bsp, AccelType::Grid}) {
        AccelConfig config;
        config.type = type;
        // Room for 1.5 references per triangle beyond the fixed part.
        config.memory_budget = fixed_build_bytes(config, n) + bytes_per_reference(config) * n * 3 / 2;
        if (type == AccelType::Grid) {  // the grid cannot leave triangles out: room for what it needs, and no more
            config.memory_budget = 0;
            const auto free = build_accelerator(scene.mesh, config);
            ASSERT_TRUE(free) << free.error();
            const uint64_t references = (*free)->stats()["references"].get<uint64_t>();
            config.memory_budget = fixed_build_bytes(config, n) + bytes_per_reference(config) * references;
        }
        const auto built = build_accelerator(scene.mesh, config);
        ASSERT_TRUE(built) << to_string(type) << ": " << built.error();
        const auto stats = (*built)->stats();
        bool noted = false;
        for (const auto& note : stats["notes"]) noted |= note.get<std::string>().find("memory budget") != std::string::npos;
        EXPECT_TRUE(noted) << to_string(type) << " " << stats["notes"].dump();
        if (type != AccelType::Grid) {
            EXPECT_LE(stats["duplication"].get<double>(), 1.5 + 1e-9) << to_string(type);
        }
        size_t wrong = 0;
        for (size_t i = 0; i < scene.rays.size(); ++i)
            if (!same_hit((*built)->intersect_closest(scene.rays[i]), scene.answers[i])) ++wrong;
        EXPECT_EQ(wrong, 0u) << to_string(type);
    }
}

}  // namespace
