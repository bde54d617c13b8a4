// The wide BVH (4 and 8 children per node) returns exactly what brute force
// returns (same triangle, bit-identical t, u, v) for the closest hit by both
// algorithms and for any-hit, on the bunny and the lecture's tricky scenes; its
// SIMD box tests give exactly the scalar loop's intervals, event for event; its
// recorded events replay to the fast path's answer; and the collapsed tree covers
// the binary one's triangles once, in its order, with children inside their parent.
#include <gtest/gtest.h>

#include <atomic>
#include <bit>
#include <mutex>
#include <algorithm>
#include <set>

#include <tbb/parallel_for.h>

#include "accel/accel_test_support.h"
#include "core/accel/bvh_build.h"
#include "core/accel/wide_bvh.h"
#include "core/geometry/scene.h"
#include "core/traversal/replay.h"
#include "test_support.h"

using namespace accelviz;
using namespace accelviz::test;

namespace {

constexpr size_t kRays = rays_for_this_build(50'000);

Mesh scene(const std::string& source) {
    auto mesh = load_scene(source);
    EXPECT_TRUE(mesh.ok()) << source << ": " << mesh.error();
    return mesh.ok() ? *mesh : Mesh{};
}

template <int W, class Lanes = FastLanes<W>>
WideBvh<W, Lanes> build_wide(const Mesh& mesh, BvhConfig config = {},
                             TriangleTestKind test = TriangleTestKind::MollerTrumbore) {
    Bvh binary = *build_bvh(mesh, config);
    binary.triangle_test = test;
    if (test == TriangleTestKind::Watertight) binary.corners = make_corners(mesh, binary.prim_ids);
    auto wide = collapse_bvh_with<W, Lanes>(std::move(binary));
    EXPECT_TRUE(wide.ok()) << wide.error();
    return std::move(*wide);
}

/// Same kind and fields, floats compared bit for bit.
bool same_event(const TraversalEvent& a, const TraversalEvent& b) {
    auto bits = [](float f) { return std::bit_cast<uint32_t>(f); };
    return a.kind == b.kind && a.reason == b.reason && a.hit == b.hit && a.node == b.node && a.tri == b.tri &&
           a.first == b.first && a.count == b.count && bits(a.t_enter) == bits(b.t_enter) &&
           bits(a.t_exit) == bits(b.t_exit) && bits(a.t) == bits(b.t) && bits(a.u) == bits(b.u) &&
           bits(a.v) == bits(b.v);
}

/// Checks widths 4 and 8 on `mesh` against brute force: closest hit by algorithm 2
/// (every ray) and algorithm 1 and any-hit (every fourth); every 16th ray also
/// through the counting and recording observers, the replay, and the scalar lanes.
template <int W>
void check_width(const Mesh& mesh, const std::vector<Ray>& rays, const std::vector<Hit>& expected,
                 const BvhConfig& config, TriangleTestKind test, const std::string& label) {
    SCOPED_TRACE(label + ", width " + std::to_string(W) + " on " + mesh.name);
    WideBvh<W> wide = build_wide<W>(mesh, config, test);
    const WideBvh<W, ScalarLanes<W>> scalar = build_wide<W, ScalarLanes<W>>(mesh, config, test);
    WideBvh<W> unordered = build_wide<W>(mesh, config, test);
    unordered.traversal = BvhTraversal::Unordered;
    std::mutex report_mutex;
    int reported = 0;
    auto report = [&](const std::string& what) {
        std::lock_guard lock(report_mutex);
        if (reported++ < 8) ADD_FAILURE() << what;
    };
    tbb::parallel_for(tbb::blocked_range<size_t>(0, rays.size(), 256), [&](const tbb::blocked_range<size_t>& range) {
        for (size_t i = range.begin(); i < range.end(); ++i) {
            const Ray& ray = rays[i];
            NoObserver none;
            const Hit closest = wide.intersect_closest(ray, none);
            if (!same_hit(closest, expected[i]))
                report("ordered: " + describe(closest) + ", brute force: " + describe(expected[i]) + " for " +
                       describe(ray));
            if (i % 4 != 0) continue;
            const Hit lane_order = unordered.intersect_closest(ray, none);
            if (!same_hit(lane_order, expected[i]))
                report("unordered: " + describe(lane_order) + ", brute force: " + describe(expected[i]) + " for " +
                       describe(ray));
            if (wide.intersect_any(ray) != expected[i].found())
                report("any-hit disagrees with brute force (" + describe(expected[i]) + ") for " + describe(ray));
            if (i % 16 != 0) continue;

            // The same walk, watched: same answer, same counters, and the scalar lanes'
            // events are the SIMD lanes' events bit for bit.
            RecordingObserver recorded, recorded_scalar;
            CountingObserver counted;
            const Hit traced = wide.intersect_closest(ray, recorded);
            wide.intersect_closest(ray, counted);
            scalar.intersect_closest(ray, recorded_scalar);
            if (!same_hit(traced, closest)) report("the recording observer changed the result for " + describe(ray));
            if (!(recorded.counters() == counted.counters))
                report("the trace's counters differ from the counting observer's for " + describe(ray));
            bool same_events = recorded.events.size() == recorded_scalar.events.size();
            for (size_t e = 0; same_events && e < recorded.events.size(); ++e)
                same_events = same_event(recorded.events[e], recorded_scalar.events[e]);
            if (!same_events) report("the scalar lanes' events differ from the SIMD lanes' for " + describe(ray));

            // Stepping is replay: the last step's state holds the fast path's answer.
            const StepState end = replay(recorded.events, recorded.events.size());
            if (!end.done || !same_hit(end.closest, closest) || !end.stack.empty())
                report("replaying the events does not end with the fast path's answer for " + describe(ray));

            // Any-hit, watched and scalar.
            RecordingObserver any_recorded;
            const bool any = wide.intersect_any(ray, any_recorded);
            NoObserver scalar_none;
            if (any != expected[i].found() || any_recorded.events.back().hit != any ||
                scalar.intersect_any(ray, scalar_none) != any)
                report("any-hit: the trace or the scalar lanes differ for " + describe(ray));
        }
    });
}

void check_scene(const Mesh& mesh, size_t ray_count, uint64_t seed) {
    const std::vector<Ray> rays = make_test_rays(mesh, ray_count, seed);
    const std::vector<Hit> expected = brute_force_answers(mesh, rays);
    const std::pair<std::string, BvhConfig> configs[] = {
        {"sah-binned", {}},
        {"midpoint leaf=1", {.builder = BvhBuilder::Midpoint, .max_leaf_size = 1}},
        {"median leaf=16", {.builder = BvhBuilder::Median, .max_leaf_size = 16}},
    };
    for (const auto& [label, config] : configs) {
        check_width<4>(mesh, rays, expected, config, TriangleTestKind::MollerTrumbore, label);
        check_width<8>(mesh, rays, expected, config, TriangleTestKind::MollerTrumbore, label);
    }
    const std::vector<Hit> watertight = brute_force_answers(mesh, rays, TriangleTestKind::Watertight);
    check_width<8>(mesh, rays, watertight, {}, TriangleTestKind::Watertight, "sah-binned watertight");
}

}  // namespace

TEST(WideBvhMatchesBruteForce, SlowBunny) {
    if (!shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    check_scene(scene(shared_asset("bunny.obj")), 100'000, 11);
}
TEST(WideBvhMatchesBruteForce, SameCentroid) { check_scene(scene("builtin:same-centroid"), kRays, 12); }
TEST(WideBvhMatchesBruteForce, SameBox) { check_scene(scene("builtin:same-box"), kRays, 13); }
TEST(WideBvhMatchesBruteForce, Stadium) { check_scene(scene("builtin:stadium"), kRays, 14); }
TEST(WideBvhMatchesBruteForce, Soup) { check_scene(scene("builtin:soup?n=2000&seed=7"), kRays, 15); }
TEST(WideBvhMatchesBruteForce, Empty) { check_scene(scene("builtin:empty"), kRays / 10, 16); }
TEST(WideBvhMatchesBruteForce, SingleTriangle) { check_scene(scene("builtin:single"), kRays / 10, 17); }
TEST(WideBvhMatchesBruteForce, CornellBox) { check_scene(scene("builtin:cornell"), kRays, 18); }
TEST(WideBvhMatchesBruteForce, Teapot) { check_scene(scene("builtin:teapot?n=6"), kRays, 19); }

// The collapse keeps the binary tree's triangle order: the wide leaves cover leaf
// order [0, N) exactly once; children lie inside their parent; the tree is
// shallower, and a node has fewer than W children only when all of them are leaves.
TEST(WideBvhCollapse, LeavesCoverTheTrianglesOnceInTheBinaryOrder) {
    const Mesh mesh = scene("builtin:soup?n=5000&seed=3");
    for (int leaf_size : {1, 4, 9}) {
        const Bvh binary = *build_bvh(mesh, {.max_leaf_size = leaf_size});
        std::set<std::pair<uint32_t, uint32_t>> binary_leaves;
        for (const BvhNode& n : binary.nodes)
            if (n.is_leaf()) binary_leaves.insert({n.first, n.count});

        for (int width : {4, 8}) {
            SCOPED_TRACE("width " + std::to_string(width) + ", leaves of at most " + std::to_string(leaf_size));
            auto check = [&](const auto& wide) {
                std::vector<std::pair<uint32_t, uint32_t>> leaves;  // (first, count)
                std::vector<int> parent_of(wide.nodes.size(), -1);
                std::vector<uint32_t> slot_to(wide.nodes.size(), 0);  // the slot pointing at each wide node
                for (size_t n = 0; n < wide.nodes.size(); ++n)
                    for (int i = 0; i < wide.nodes[n].child_count; ++i)
                        if (!wide.nodes[n].is_leaf(i)) slot_to[wide.nodes[n].first[i]] = wide.slot_of(uint32_t(n), i);
                for (size_t n = 0; n < wide.nodes.size(); ++n) {
                    const auto& node = wide.nodes[n];
                    EXPECT_GE(node.child_count, 2);
                    EXPECT_LE(int(node.child_count), width);
                    if (node.child_count < width) {  // the collapse stops opening only when every child is a leaf
                        for (int i = 0; i < node.child_count; ++i) EXPECT_TRUE(node.is_leaf(i));
                    }
                    const Aabb parent = wide.box_of(slot_to[n]);
                    for (int i = 0; i < node.child_count; ++i) {
                        const Aabb box = node.boxes.get(i);
                        EXPECT_TRUE(parent.lo.x <= box.lo.x && parent.lo.y <= box.lo.y && parent.lo.z <= box.lo.z &&
                                    box.hi.x <= parent.hi.x && box.hi.y <= parent.hi.y && box.hi.z <= parent.hi.z);
                        if (node.is_leaf(i)) {
                            leaves.push_back({node.first[i], node.count[i]});
                            EXPECT_TRUE(binary_leaves.count({node.first[i], node.count[i]}))
                                << "a leaf of " << node.count[i] << " triangles that the binary tree did not make";
                        } else {
                            ASSERT_LT(node.first[i], wide.nodes.size());
                            EXPECT_EQ(parent_of[node.first[i]], -1) << "a wide node with two parents";
                            parent_of[node.first[i]] = int(n);
                        }
                    }
                }
                std::sort(leaves.begin(), leaves.end());
                uint32_t next = 0;
                for (const auto& [first, count] : leaves) {
                    EXPECT_EQ(first, next) << "the leaves must cover leaf order without gaps or overlaps";
                    next = first + count;
                }
                EXPECT_EQ(next, mesh.triangle_count());
                EXPECT_EQ(wide.build_stats.nodes, wide.nodes.size());
                EXPECT_EQ(wide.build_stats.leaves, leaves.size());
                EXPECT_GT(wide.build_stats.avg_children, 2.5);  // the binary tree has 2
                EXPECT_LT(wide.build_stats.max_depth, binary.build_stats.max_depth);
                EXPECT_EQ(wide.prim_ids, binary.prim_ids);
                EXPECT_EQ(wide.build_stats.bytes_per_node, width == 4 ? 128u : 256u);
            };
            Bvh copy = binary;
            if (width == 4) check(*collapse_bvh<4>(std::move(copy)));
            else check(*collapse_bvh<8>(std::move(copy)));
        }
    }
}

// The leaves are the binary tree's, whatever the leaf size: with a large one
// allowed, merging every small subtree would leave leaves of dozens of triangles (ten
// times the triangle tests per ray).
TEST(WideBvhCollapse, TheLeavesAreTheBinaryTreesAtAnyLeafSize) {
    const Mesh mesh = scene("builtin:soup?n=5000&seed=3");
    for (const BvhConfig& config : {BvhConfig{.max_leaf_size = 255}, BvhConfig{.builder = BvhBuilder::Midpoint, .max_leaf_size = 6}}) {
        const Bvh binary = *build_bvh(mesh, config);
        std::set<std::pair<uint32_t, uint32_t>> binary_leaves;
        for (const BvhNode& n : binary.nodes)
            if (n.is_leaf()) binary_leaves.insert({n.first, n.count});
        Bvh copy = binary;
        const auto wide = *collapse_bvh<8>(std::move(copy));
        EXPECT_EQ(wide.build_stats.leaves, binary_leaves.size());
        for (const auto& node : wide.nodes)
            for (int i = 0; i < node.child_count; ++i)
                if (node.is_leaf(i)) {
                    EXPECT_TRUE(binary_leaves.count({node.first[i], node.count[i]}));
                }
    }
}

// A wide node's events: one BoxTest per child in lane order, then the culls, then
// the pushes farthest first, so the nearest kept child is visited next.
TEST(WideBvhEvents, AWideNodeTestsAllItsChildrenThenPushesFarthestFirst) {
    const Mesh mesh = scene("builtin:soup?n=3000&seed=5");
    const WideBvh<8> wide = build_wide<8>(mesh);
    const std::vector<Ray> rays = make_test_rays(mesh, 2000, 21);
    int nodes_checked = 0;
    for (const Ray& ray : rays) {
        RecordingObserver rec;
        wide.intersect_closest(ray, rec);
        const auto& ev = rec.events;
        for (size_t e = 0; e + 1 < ev.size(); ++e) {
            if (ev[e].kind != EventKind::VisitNode || ev[e + 1].kind != EventKind::BoxTest) continue;
            // The box tests of one node: consecutive slots.
            size_t k = e + 1;
            while (k < ev.size() && ev[k].kind == EventKind::BoxTest) ++k;
            const size_t tests = k - (e + 1);
            ASSERT_GE(tests, 2u);
            for (size_t j = e + 2; j < k; ++j) EXPECT_EQ(ev[j].node, ev[j - 1].node + 1);
            while (k < ev.size() && ev[k].kind == EventKind::Cull) ++k;
            float last_pushed = kInfinity;
            while (k < ev.size() && ev[k].kind == EventKind::Push) {
                EXPECT_LE(ev[k].t_enter, last_pushed) << "pushes go farthest first";
                last_pushed = ev[k].t_enter;
                ++k;
            }
            if (k < ev.size() && ev[k].kind == EventKind::VisitNode) {
                EXPECT_LE(ev[k].t_enter, last_pushed);
            }
            ++nodes_checked;
        }
    }
    EXPECT_GT(nodes_checked, 1000);
}

// Through the factory: --bvh-width picks the wide tree, and its config says so.
TEST(WideBvhFactory, WidthSelectsTheTree) {
    const Mesh mesh = scene("builtin:soup?n=500&seed=1");
    for (int width : {2, 4, 8}) {
        AccelConfig config;
        config.type = AccelType::Bvh;
        config.bvh.width = width;
        auto accel = build_accelerator(mesh, config);
        ASSERT_TRUE(accel.ok()) << accel.error();
        EXPECT_EQ((*accel)->config()["width"], width);
        EXPECT_EQ((*accel)->type(), AccelType::Bvh);
        EXPECT_EQ(structure_if<Bvh>(**accel) != nullptr, width == 2);
        EXPECT_EQ(structure_if<WideBvh<4>>(**accel) != nullptr, width == 4);
        EXPECT_EQ(structure_if<WideBvh<8>>(**accel) != nullptr, width == 8);
    }
    AccelConfig bad;
    bad.type = AccelType::Bvh;
    bad.bvh.width = 3;
    auto refused = build_accelerator(mesh, bad);
    ASSERT_FALSE(refused.ok());
    EXPECT_NE(refused.error().find("--bvh-width"), std::string::npos);
}
