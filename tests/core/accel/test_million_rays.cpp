// A million rays (label long: about 4 minutes on 2 cores): every structure in every configuration
// (test::all_configurations) answers 10^6 seeded rays per scene exactly as brute
// force does, closest hit (triangle and bit-identical t, u, v) and any hit, on the
// lecture's tricky scenes and on a scanned mesh. The rays are of the kinds that break
// structures (accel_test_support.h): axis-parallel, ±0 components, origins on
// planes and inside boxes, rays aimed at vertices, finite ranges. The two tricky
// scenes have 100 triangles: every ray meets all of them in one cell, and the grid
// without a mailbox tests each once per cell (1000 took 5 minutes per scene).
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>

#include <tbb/parallel_for.h>

#include "accel_test_support.h"
#include "core/geometry/scene.h"
#include "test_support.h"

namespace accelviz {
namespace {

constexpr size_t kRays = 1'000'000;

void check_million(const std::string& source, uint64_t seed) {
    auto mesh = load_scene(source);
    ASSERT_TRUE(mesh) << mesh.error();
    const std::vector<Ray> rays = test::make_test_rays(*mesh, kRays, seed);
    std::vector<Hit> answers[2];  // by TriangleTestKind, computed when first needed
    for (const auto& [label, config] : test::all_configurations()) {
        std::vector<Hit>& want = answers[int(config.triangle_test)];
        if (want.empty()) want = test::brute_force_answers(*mesh, rays, config.triangle_test);
        SCOPED_TRACE(label + " on " + source);
        auto built = build_accelerator(*mesh, config);
        ASSERT_TRUE(built) << built.error();
        const Accelerator& accel = **built;
        std::atomic<size_t> wrong = 0;
        std::mutex report_mutex;
        tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 1024), [&](const tbb::blocked_range<size_t>& range) {
            for (size_t i = range.begin(); i < range.end(); ++i) {
                const Hit got = accel.intersect_closest(rays[i]);
                const bool any = accel.intersect_any(rays[i]);
                if (test::same_hit(got, want[i]) && any == want[i].found()) continue;
                if (wrong++ < 5) {
                    std::lock_guard lock(report_mutex);
                    ADD_FAILURE() << test::describe(rays[i]) << ": got " << test::describe(got) << " (any-hit "
                                  << (any ? "hit" : "miss") << "), brute force " << test::describe(want[i]);
                }
            }
        });
        EXPECT_EQ(wrong.load(), 0u);
    }
}

TEST(MillionRaysLong, SameCentroid) { check_million("builtin:same-centroid?n=100", 101); }
TEST(MillionRaysLong, SameBox) { check_million("builtin:same-box?n=100", 102); }
TEST(MillionRaysLong, Stadium) { check_million("builtin:stadium", 103); }
TEST(MillionRaysLong, Soup) { check_million("builtin:soup?n=3000&seed=4", 104); }
TEST(MillionRaysLong, Cornell) { check_million("builtin:cornell", 105); }
TEST(MillionRaysLong, Teapot) { check_million("builtin:teapot?n=16", 106); }
TEST(MillionRaysLong, Bunny) {
    if (!test::shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    check_million(test::shared_asset("bunny.obj"), 107);
}

}  // namespace
}  // namespace accelviz
