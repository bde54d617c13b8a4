// Every BVH builder × traversal returns exactly what brute force returns (same
// triangle id, bit-identical t, u, v) on seeded random rays, on the bunny and on
// the lecture's tricky scenes; the recorded trace agrees with the fast path; and
// algorithm 2 never visits more nodes than algorithm 1.
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>

#include <tbb/parallel_for.h>

#include "accel/accel_test_support.h"
#include "core/accel/bvh_build.h"
#include "core/geometry/scene.h"
#include "test_support.h"

using namespace accelviz;
using namespace accelviz::test;

namespace {

constexpr size_t kRays = rays_for_this_build(100'000);

struct Variant {
    std::string label;
    BvhConfig config;
};

/// The four builders with their defaults, plus the parameter extremes.
std::vector<Variant> variants() {
    std::vector<Variant> v;
    for (BvhBuilder b : {BvhBuilder::Midpoint, BvhBuilder::Median, BvhBuilder::SahSweep, BvhBuilder::SahBinned})
        v.push_back({std::string(to_string(b)), BvhConfig{.builder = b}});
    v.push_back({"sah-binned bins=2", {.builder = BvhBuilder::SahBinned, .bins = 2}});
    v.push_back({"sah-binned bins=64", {.builder = BvhBuilder::SahBinned, .bins = 64}});
    v.push_back({"sah-binned leaf=1", {.builder = BvhBuilder::SahBinned, .max_leaf_size = 1}});
    v.push_back({"sah-binned cost_trav=0", {.builder = BvhBuilder::SahBinned, .cost_trav = 0.0f}});
    v.push_back({"sah-sweep leaf=16 cost_isect=8",
                 {.builder = BvhBuilder::SahSweep, .max_leaf_size = 16, .cost_isect = 8.0f}});
    v.push_back({"midpoint leaf=1", {.builder = BvhBuilder::Midpoint, .max_leaf_size = 1}});
    v.push_back({"median leaf=32", {.builder = BvhBuilder::Median, .max_leaf_size = 32}});
    return v;
}

/// Checks every variant on `mesh` against the brute-force answers, computed once.
/// The four default builders see every ray; the parameter extremes every twentieth.
/// Returns the nodes visited (ordered, unordered) by the default sah-binned tree
/// over the rays it counted.
std::pair<uint64_t, uint64_t> check_scene(const Mesh& mesh, size_t ray_count, uint64_t seed) {
    const std::vector<Ray> rays = make_test_rays(mesh, ray_count, seed);
    const std::vector<Hit> expected = brute_force_answers(mesh, rays);

    // The oracle itself: BruteForce on a sample of the rays.
    const BruteForce brute(mesh);
    for (size_t i = 0; i < rays.size(); i += 97) {
        NoObserver none;
        const Hit h = brute.intersect_closest(rays[i], none);
        EXPECT_TRUE(same_hit(h, expected[i])) << "oracle disagrees with BruteForce on " << describe(rays[i]);
    }

    std::pair<uint64_t, uint64_t> default_visits{0, 0};
    const std::vector<Variant> all = variants();
    for (size_t v = 0; v < all.size(); ++v) {
        const Variant& variant = all[v];
        SCOPED_TRACE(variant.label + " on " + mesh.name);
        const size_t stride = v < 4 ? 1 : 20;
        const Bvh bvh = *build_bvh(mesh, variant.config);
        std::atomic<uint64_t> visits[2] = {0, 0};
        std::mutex report_mutex;
        int reported = 0;
        auto report = [&](const std::string& what) {
            std::lock_guard lock(report_mutex);
            if (reported++ < 8) ADD_FAILURE() << what;
        };
        tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size() / stride, 256), [&](const tbb::blocked_range<size_t>& range) {
            uint64_t local_visits[2] = {0, 0};
            for (size_t j = range.begin(); j < range.end(); ++j) {
                const size_t i = j * stride;
                const Ray& ray = rays[i];
                NoObserver none;
                const Hit ordered = bvh.intersect_ordered(ray, none);
                const Hit unordered = bvh.intersect_unordered(ray, none);
                const bool any = bvh.intersect_any(ray);
                if (!same_hit(ordered, expected[i]))
                    report("ordered: " + describe(ordered) + ", brute force: " + describe(expected[i]) + " for " +
                           describe(ray));
                if (!same_hit(unordered, expected[i]))
                    report("unordered: " + describe(unordered) + ", brute force: " + describe(expected[i]) + " for " +
                           describe(ray));
                if (any != expected[i].found())
                    report(std::string("any-hit says ") + (any ? "hit" : "miss") + ", brute force: " +
                           describe(expected[i]) + " for " + describe(ray));
                if (j % 8 != 0) continue;

                // Work: algorithm 2 visits a subset of algorithm 1's nodes, ray by ray.
                CountingObserver counted[2];
                const Hit ordered_counted = bvh.intersect_ordered(ray, counted[0]);
                const Hit unordered_counted = bvh.intersect_unordered(ray, counted[1]);
                if (!same_hit(ordered_counted, ordered) || !same_hit(unordered_counted, unordered))
                    report("the counting observer changed the result for " + describe(ray));
                if (counted[0].counters.nodes_visited > counted[1].counters.nodes_visited)
                    report("algorithm 2 visited " + std::to_string(counted[0].counters.nodes_visited) +
                           " nodes, algorithm 1 only " + std::to_string(counted[1].counters.nodes_visited) + " for " +
                           describe(ray));
                local_visits[0] += counted[0].counters.nodes_visited;
                local_visits[1] += counted[1].counters.nodes_visited;
                if (j % 40 != 0) continue;

                // The recorded trace: same answer as the fast path, same counters as the counting observer.
                for (BvhTraversal traversal : {BvhTraversal::Ordered, BvhTraversal::Unordered}) {
                    const bool is_ordered = traversal == BvhTraversal::Ordered;
                    RecordingObserver recorder;
                    const Hit traced = is_ordered ? bvh.intersect_ordered(ray, recorder) : bvh.intersect_unordered(ray, recorder);
                    const Hit& fast = is_ordered ? ordered : unordered;
                    const TraversalEvent& last = recorder.events.back();
                    const Hit done = last.hit ? Hit{last.tri, last.t, last.u, last.v} : Hit{};
                    if (last.kind != EventKind::Done || !same_hit(done, fast) || !same_hit(traced, fast))
                        report(std::string(to_string(traversal)) + ": the trace's Done event differs from the fast path for " +
                               describe(ray));
                    if (!(recorder.counters() == counted[is_ordered ? 0 : 1].counters))
                        report(std::string(to_string(traversal)) +
                               ": the trace's counters differ from the counting observer's for " + describe(ray));
                }
                RecordingObserver any_recorder;
                if (bvh.intersect_any(ray, any_recorder) != any || any_recorder.events.back().hit != any)
                    report("any-hit: the trace differs from the fast path for " + describe(ray));
            }
            visits[0] += local_visits[0];
            visits[1] += local_visits[1];
        });
        EXPECT_LE(visits[0].load(), visits[1].load()) << "algorithm 2 must not visit more nodes than algorithm 1";
        if (variant.label == "sah-binned") default_visits = {visits[0].load(), visits[1].load()};
    }
    return default_visits;
}

Mesh scene(const std::string& source) {
    auto mesh = load_scene(source);
    EXPECT_TRUE(mesh.ok()) << source << ": " << mesh.error();
    return mesh.ok() ? *mesh : Mesh{};
}

}  // namespace

TEST(BvhMatchesBruteForce, SlowBunny) {
    if (!shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    const Mesh mesh = scene(shared_asset("bunny.obj"));
    ASSERT_GT(mesh.triangle_count(), 60000u);
    const auto [ordered, unordered] = check_scene(mesh, kRays, 1);
    EXPECT_LT(ordered, unordered) << "on the bunny algorithm 2 must visit strictly fewer nodes than algorithm 1";
}

// The lecture's tricky cases (棘手的情况) and the teapot in a stadium.
TEST(BvhMatchesBruteForce, SameCentroid) { check_scene(scene("builtin:same-centroid"), kRays, 2); }
TEST(BvhMatchesBruteForce, SameBox) { check_scene(scene("builtin:same-box"), kRays, 3); }
TEST(BvhMatchesBruteForce, Stadium) { check_scene(scene("builtin:stadium"), kRays, 4); }
TEST(BvhMatchesBruteForce, Soup) { check_scene(scene("builtin:soup?n=2000&seed=7"), kRays, 5); }
TEST(BvhMatchesBruteForce, Empty) { check_scene(scene("builtin:empty"), kRays, 6); }
TEST(BvhMatchesBruteForce, SingleTriangle) { check_scene(scene("builtin:single"), kRays, 7); }
TEST(BvhMatchesBruteForce, CornellBox) { check_scene(scene("builtin:cornell"), kRays, 8); }
TEST(BvhMatchesBruteForce, Teapot) { check_scene(scene("builtin:teapot?n=6"), kRays, 9); }
