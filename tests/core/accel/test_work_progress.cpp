// Progress and cancel of loads and builds (what the window's progress bar and
// Cancel button use): every build counts its stage to the end, a cancelled build
// or load stops and says "cancelled", and watching a build does not change it.
#include <gtest/gtest.h>

#include <filesystem>
#include <atomic>
#include <fstream>
#include <set>
#include <string>
#include <thread>

#include "accel/accel_test_support.h"
#include "core/accel/factory.h"
#include "core/accel/spatial_refs.h"
#include "core/geometry/scene.h"
#include "core/util/work_progress.h"

using namespace accelviz;

namespace {

const std::vector<AccelType> kBuiltTypes = {AccelType::Bvh, AccelType::Grid, AccelType::Kd, AccelType::Octree,
                                            AccelType::Bsp};

Mesh soup(int n) {
    auto mesh = load_scene("builtin:soup?n=" + std::to_string(n) + "&seed=3");
    if (!mesh) throw std::runtime_error(mesh.error());
    return std::move(*mesh);
}

AccelConfig config_of(AccelType type) {
    AccelConfig config;
    config.type = type;
    return config;
}

bool is_cancelled(const Expected<std::shared_ptr<const Accelerator>>& built) {
    return !built && built.error() == WorkProgress::cancelled_error().message;
}

TEST(WorkProgress, EveryBuildCountsItsStageToTheEnd) {
    const Mesh mesh = soup(30000);  // big enough for the parallel parts of every build
    for (AccelType type : kBuiltTypes) {
        WorkProgress progress;
        const auto built = build_accelerator(mesh, config_of(type), &progress);
        ASSERT_TRUE(built) << built.error();
        // The units add up to the total whatever the duplication (KD tree, octree), in
        // the last stage and in those before it (the trees' own, before the leaf-order copy).
        EXPECT_NEAR(progress.fraction(), 1.0, 1e-6) << to_string(type);
        EXPECT_TRUE(progress.earlier_stages_finished()) << to_string(type);
        EXPECT_FALSE(progress.cancelled());
    }
}

TEST(WorkProgress, ANodeCountsItsOwnPartAndHandsOnTheRest) {
    // count_part: how the top of a KD tree or octree, and every BSP split, moves the
    // bar before any leaf exists; what it hands on adds up to the node's units.
    WorkProgress shared;
    shared.start_stage(PartitionProgress::kTotal);
    {
        PartitionProgress progress(&shared);
        const uint64_t rest = progress.count_part(PartitionProgress::kTotal, kTopParts);
        EXPECT_EQ(rest, PartitionProgress::kTotal - PartitionProgress::kTotal / kTopParts);
        progress.flush();
        EXPECT_DOUBLE_EQ(shared.fraction(), 1.0 / double(kTopParts));
        const uint64_t half = PartitionProgress::share_of(rest, 1, 2);
        progress.leaf_done(half);
        progress.leaf_done(rest - half);
    }
    EXPECT_DOUBLE_EQ(shared.fraction(), 1.0);
}

TEST(WorkProgress, TheLongPartsOfATreeBuildAreStagesTheWindowNames) {
    // Subtrees that ran out of their share of the reference budget are built again, and
    // the triangles are copied (the octree: one copy each), each in a stage of its own, named (the
    // bar would otherwise wait at its end meanwhile: seconds at ten million triangles).
    // Watched from another thread, as the window does.
    const Mesh mesh = soup(200000);
    AccelConfig config = config_of(AccelType::Octree);
    config.octree.max_duplication = 1.5;
    WorkProgress progress;
    std::atomic<bool> done{false};
    std::set<std::string> labels;
    std::thread watcher([&] {
        while (!done.load()) {
            if (const char* label = progress.stage_label()) labels.insert(label);
            std::this_thread::yield();
        }
    });
    const auto built = build_accelerator(mesh, config, &progress);
    done = true;
    watcher.join();
    ASSERT_TRUE(built) << built.error();
    ASSERT_NE((*built)->stats()["notes"].dump().find("reference budget"), std::string::npos);
    bool again = false;
    for (const std::string& label : labels) again |= label.find("reference budget") != std::string::npos;
    EXPECT_TRUE(again);
    ASSERT_NE(progress.stage_label(), nullptr);
    EXPECT_EQ(std::string(progress.stage_label()), "copying the triangles");  // one per triangle: the octree's
    EXPECT_NEAR(progress.fraction(), 1.0, 1e-6);
    EXPECT_TRUE(progress.earlier_stages_finished());
}

TEST(WorkProgress, ACancelledBuildStopsAndSaysSo) {
    const Mesh mesh = soup(20000);
    for (AccelType type : kBuiltTypes) {
        WorkProgress progress;
        progress.cancel();
        const auto built = build_accelerator(mesh, config_of(type), &progress);
        EXPECT_TRUE(is_cancelled(built)) << to_string(type) << ": " << (built ? "built" : built.error());
    }
}

TEST(WorkProgress, ABuildCancelledWhileRunningStops) {
    // The KD tree and the octree over 200k triangles take a few tenths of a second or
    // more here: cancelled once a tenth is done, each must give up rather than finish.
    const Mesh mesh = soup(200000);
    for (AccelType type : {AccelType::Kd, AccelType::Octree}) {
        WorkProgress progress;
        Expected<std::shared_ptr<const Accelerator>> built = Error{"not run"};
        std::thread worker([&] { built = build_accelerator(mesh, config_of(type), &progress); });
        while (progress.fraction() < 0.1) std::this_thread::yield();
        progress.cancel();
        worker.join();
        EXPECT_TRUE(is_cancelled(built)) << to_string(type) << ": " << (built ? "built" : built.error());
    }
}

TEST(WorkProgress, WatchingABuildDoesNotChangeIt) {
    const Mesh mesh = soup(20000);
    const std::vector<Ray> rays = test::make_test_rays(mesh, 2000, 17);
    for (AccelType type : kBuiltTypes) {
        WorkProgress progress;
        const auto watched = build_accelerator(mesh, config_of(type), &progress);
        const auto plain = build_accelerator(mesh, config_of(type));
        ASSERT_TRUE(watched && plain);
        nlohmann::json a = (*watched)->stats(), b = (*plain)->stats();
        a.erase("build_ms");
        b.erase("build_ms");
        EXPECT_EQ(a, b) << to_string(type);
        for (const Ray& ray : rays) {
            const Hit x = (*watched)->intersect_closest(ray), y = (*plain)->intersect_closest(ray);
            ASSERT_TRUE(test::same_hit(x, y)) << to_string(type);
        }
    }
}

TEST(WorkProgress, AnObjLoadCountsItsBytesAndCanBeCancelled) {
    const auto path = std::filesystem::temp_directory_path() / "accelviz_progress_test.obj";
    {
        std::ofstream out(path);
        for (int i = 0; i < 3000; ++i)
            out << "v " << i << " 0 0\nv " << i << " 1 0\nv " << i << " 0 1\nf " << 3 * i + 1 << ' ' << 3 * i + 2
                << ' ' << 3 * i + 3 << '\n';
    }
    WorkProgress progress;
    const auto mesh = load_obj(path.string(), &progress);
    ASSERT_TRUE(mesh) << mesh.error();
    EXPECT_EQ(mesh->triangle_count(), 3000u);
    EXPECT_NEAR(progress.fraction(), 1.0, 1e-9);

    WorkProgress cancelled;
    cancelled.cancel();
    const auto stopped = load_obj(path.string(), &cancelled);
    ASSERT_FALSE(stopped);
    EXPECT_EQ(stopped.error(), WorkProgress::cancelled_error().message);
    std::filesystem::remove(path);
}

TEST(WorkProgress, InstancesCountTheLoadOfTheirMeshAndCanBeCancelled) {
    // builtin:instances loads its mesh= through load_scene: the window's bar follows
    // that load too, and its Cancel stops it.
    const auto path = std::filesystem::temp_directory_path() / "accelviz_progress_instances.obj";
    {
        std::ofstream out(path);
        for (int i = 0; i < 2000; ++i)
            out << "v " << i << " 0 0\nv " << i << " 1 0\nv " << i << " 0 1\nf " << 3 * i + 1 << ' ' << 3 * i + 2
                << ' ' << 3 * i + 3 << '\n';
    }
    const std::string source = "builtin:instances?mesh=" + path.string() + "&nx=2&nz=3";
    WorkProgress progress;
    const auto mesh = load_scene(source, MeshCache::Skip, &progress);
    ASSERT_TRUE(mesh) << mesh.error();
    EXPECT_EQ(mesh->triangle_count(), 6 * 2000u);
    EXPECT_NEAR(progress.fraction(), 1.0, 1e-9);

    WorkProgress cancelled;
    cancelled.cancel();
    const auto stopped = load_scene(source, MeshCache::Skip, &cancelled);
    ASSERT_FALSE(stopped);
    EXPECT_EQ(stopped.error(), WorkProgress::cancelled_error().message);  // not wrapped in the scene's name
    std::filesystem::remove(path);
}

}  // namespace
