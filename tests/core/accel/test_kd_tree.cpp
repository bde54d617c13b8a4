// The KD tree: exact against brute force in every configuration, the lecture's
// pitfall made visible by --kd-strict-cell off, and the tree's invariants.
#include <bit>

#include <gtest/gtest.h>

#include <cstring>

#include <tbb/global_control.h>

#include "accel/space_partition_support.h"
#include "core/accel/kd_sah.h"
#include "core/accel/kd_tree.h"
#include "core/geometry/triangle_box.h"
#include "core/util/random.h"

using namespace accelviz;
using namespace accelviz::test;

namespace {

KdTree build(const Mesh& mesh, KdConfig config) {
    auto tree = build_kd_tree(mesh, config);
    if (!tree.ok()) throw std::runtime_error(tree.error());
    return std::move(*tree);
}

std::vector<std::pair<std::string, KdConfig>> configs() {
    std::vector<std::pair<std::string, KdConfig>> out;
    for (KdBuilder builder : {KdBuilder::Sah, KdBuilder::Median})
        for (ClipMode clip : {ClipMode::Exact, ClipMode::Box}) {
            KdConfig c;
            c.builder = builder;
            c.clip = clip;
            out.push_back({std::string(to_string(builder)) + " clip=" + std::string(to_string(clip)), c});
        }
    KdConfig with_mailbox;  // the default is off
    with_mailbox.mailbox = true;
    out.push_back({"sah mailbox=on", with_mailbox});
    KdConfig deep;
    deep.builder = KdBuilder::Median;
    deep.leaf_size = 1;
    deep.max_depth = 40;
    out.push_back({"median leaf=1 depth=40", deep});
    return out;
}

void check_scene(const std::string& source, bool skip_deep_median = false) {
    const SceneCase& scene = scene_case(source);
    for (const auto& [label, config] : configs()) {
        // On a big mesh the deep median tree only hits the reference budget, slowly.
        if (skip_deep_median && config.max_depth == 40) continue;
        const KdTree tree = build(scene.mesh, config);
        expect_exact(tree, scene, "kd " + label);
        expect_trace_agrees(tree, scene, 97, "kd " + label);
    }
}

/// Walks the tree with node boxes; calls f(node, box, depth) for every node.
template <class F>
void for_each_node(const KdTree& t, F&& f) {
    struct Item {
        uint32_t node;
        Aabb box;
        uint32_t depth;
    };
    std::vector<Item> stack{{0, t.bounds, 0}};
    while (!stack.empty()) {
        const Item it = stack.back();
        stack.pop_back();
        f(it.node, it.box, it.depth);
        const KdNode& n = t.nodes[it.node];
        if (n.is_leaf()) continue;
        Aabb lo = it.box, hi = it.box;
        lo.hi[n.axis()] = n.split();
        hi.lo[n.axis()] = n.split();
        stack.push_back({n.first(), lo, it.depth + 1});
        stack.push_back({n.first() + 1, hi, it.depth + 1});
    }
}

/// The slide's scene: a long slanted triangle A (id 0) crosses the median plane
/// x = 5; the ray along +x meets it at x = 8, behind a small triangle B (id 1)
/// standing at x = 6. The first leaf the ray walks (x < 5) holds A.
Mesh straddle_scene() {
    Mesh m;
    m.add_triangle({0, -2, -0.8f}, {0, 2, -0.8f}, {10, 0, 0.2f});
    m.add_triangle({6, -0.5f, -0.5f}, {6, 0.5f, -0.5f}, {6, 0, 0.5f});
    return m;
}

/// n random boxes whose bounds lie on a lattice of steps + 1 positions spanning the
/// node widened by `margin` on each side (a coarse lattice makes shared bounds and
/// bounds on the node's faces likely; a bound at zero is -0 or +0 at random); `flat`:
/// every box has lo == hi.
SpatialRefs lattice_refs(Rng& rng, const Aabb& node, size_t n, uint32_t steps, float margin, bool flat) {
    SpatialRefs refs;
    for (size_t i = 0; i < n; ++i) {
        Aabb b;
        for (int a = 0; a < 3; ++a) {
            const float step = (node.hi[a] - node.lo[a] + 2.0f * margin) / float(steps);
            auto coarse = [&] {
                const float v = node.lo[a] - margin + step * float(rng.below(steps + 1));
                return v == 0.0f && rng.below(2) ? -0.0f : v;
            };
            const float x = coarse(), y = coarse();
            b.lo[a] = std::min(x, y);
            b.hi[a] = flat ? b.lo[a] : std::max(x, y);
        }
        refs.push_back({uint32_t(i), b});
    }
    return refs;
}

}  // namespace

TEST(KdTree, ExactOnStadium) { check_scene("builtin:stadium"); }
TEST(KdTree, ExactOnSameBox) { check_scene("builtin:same-box"); }
TEST(KdTree, ExactOnSameCentroid) { check_scene("builtin:same-centroid"); }
TEST(KdTree, ExactOnSoup) { check_scene("builtin:soup?n=2000&seed=3"); }
TEST(KdTree, ExactOnEmptyScene) { check_scene("builtin:empty"); }
TEST(KdTree, ExactOnSingleTriangle) { check_scene("builtin:single"); }
TEST(KdTree, ExactOnCornellBox) { check_scene("builtin:cornell"); }
TEST(KdTree, SlowExactOnBunny) {
    if (!shared_asset_exists("bunny.obj")) GTEST_SKIP() << "bunny.obj not found";
    check_scene("bunny", /*skip_deep_median=*/true);
}

TEST(KdTree, StrictCellOffGivesTheSlidesWrongAnswer) {
    const Mesh m = straddle_scene();
    const Ray ray{{-1, 0, 0}, {1, 0, 0}};
    NoObserver none;
    const Hit truth = BruteForce(m).intersect_closest(ray, none);
    ASSERT_EQ(truth.tri, 1u);  // B, at x = 6
    KdConfig c;
    c.builder = KdBuilder::Median;
    c.leaf_size = 1;
    const KdTree strict = build(m, c);
    ASSERT_FALSE(strict.nodes[0].is_leaf());
    EXPECT_EQ(strict.nodes[0].axis(), 0);
    EXPECT_TRUE(same_hit(strict.intersect_closest(ray, none), truth));
    // The in-cell rule at work: A's hit is seen in the first leaf and deferred.
    RecordingObserver rec;
    strict.intersect_closest(ray, rec);
    bool deferred = false;
    for (const auto& e : rec.events) deferred |= e.kind == EventKind::HitOutsideCell && e.tri == 0;
    EXPECT_TRUE(deferred);

    c.strict_cell = false;
    const KdTree naive = build(m, c);
    const Hit wrong = naive.intersect_closest(ray, none);
    EXPECT_EQ(wrong.tri, 0u) << "the naive rule stops in the first leaf with A's hit at x = 8";
    EXPECT_GT(wrong.t, truth.t);
}

TEST(KdTree, StrictCellOffIsWrongOnRandomRaysToo) {
    // The same mistake shows on an ordinary scene: some rays get a farther triangle.
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3");
    KdConfig c;
    c.strict_cell = false;
    const KdTree naive = build(scene.mesh, c);
    size_t wrong = 0;
    NoObserver none;
    for (size_t i = 0; i < scene.rays.size(); ++i)
        if (!same_hit(naive.intersect_closest(scene.rays[i], none), scene.answers[i])) ++wrong;
    EXPECT_GT(wrong, 0u);
}

TEST(KdTree, ChildrenPartitionTheirParent) {
    const SceneCase& scene = scene_case("builtin:stadium", 10);
    for (KdBuilder b : {KdBuilder::Sah, KdBuilder::Median}) {
        KdConfig c;
        c.builder = b;
        const KdTree t = build(scene.mesh, c);
        uint32_t leaves = 0, max_depth = 0;
        uint64_t refs = 0;
        for_each_node(t, [&](uint32_t node, const Aabb& box, uint32_t depth) {
            const KdNode& n = t.nodes[node];
            max_depth = std::max(max_depth, depth);
            if (n.is_leaf()) {
                ++leaves;
                refs += n.count();
                EXPECT_LE(n.first() + n.count(), t.prim_ids.size());
                return;
            }
            // The plane lies strictly inside the box: two non-empty halves that tile it.
            EXPECT_GT(n.split(), box.lo[n.axis()]);
            EXPECT_LT(n.split(), box.hi[n.axis()]);
            EXPECT_EQ(n.first() % 2, 1u) << "children are allocated in pairs after the root";
        });
        EXPECT_EQ(leaves, t.build_stats.leaves);
        EXPECT_EQ(refs, t.prim_ids.size());
        EXPECT_EQ(max_depth, t.build_stats.max_depth);
        EXPECT_LE(max_depth, t.build_stats.depth_limit);
        EXPECT_EQ(t.nodes.size(), 2 * size_t(leaves) - 1);
        // Each leaf's triangles, as its lanes hold them, are the mesh's (bit for bit).
        for (const KdNode& n : t.nodes) {
            if (!n.is_leaf()) continue;
            for (uint32_t j = 0; j < n.count(); ++j) {
                const Triangle expected = scene.mesh.triangle(t.prim_ids[n.first() + j]);
                const Triangle got = t.leaf_lanes.get(n.first(), n.count(), j);
                EXPECT_EQ(std::memcmp(&got, &expected, sizeof(Triangle)), 0) << "leaf at " << n.first() << ", triangle " << j;
            }
        }
    }
}

TEST(KdTree, EveryTriangleIsInEveryLeafItComesNear) {
    // A triangle within (half) the padding of a leaf's box must be referenced there.
    const SceneCase& scene = scene_case("builtin:soup?n=500&seed=9", 10);
    for (ClipMode clip : {ClipMode::Exact, ClipMode::Box}) {
        KdConfig c;
        c.clip = clip;
        const KdTree t = build(scene.mesh, c);
        const float margin = 0.5f * t.build_stats.padding;
        size_t missing = 0;
        for_each_node(t, [&](uint32_t node, const Aabb& box, uint32_t) {
            const KdNode& n = t.nodes[node];
            if (!n.is_leaf()) return;
            std::vector<char> here(scene.mesh.triangle_count(), 0);
            for (uint32_t k = n.first(); k < n.first() + n.count(); ++k) here[t.prim_ids[k]] = 1;
            for (uint32_t tri = 0; tri < scene.mesh.triangle_count(); ++tri)
                if (!here[tri] && triangle_overlaps_box(scene.mesh.vertex(tri, 0), scene.mesh.vertex(tri, 1),
                                                        scene.mesh.vertex(tri, 2), padded(box, margin)))
                    ++missing;
        });
        EXPECT_EQ(missing, 0u) << to_string(clip);
    }
}

TEST(KdTree, ExactClippingStoresFewerReferences) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 10);
    KdConfig exact, box;
    box.clip = ClipMode::Box;
    EXPECT_LT(build(scene.mesh, exact).build_stats.references, build(scene.mesh, box).build_stats.references);
}

TEST(KdTree, MaxDepthDefaultsToWaldHavran) {
    KdConfig c;
    EXPECT_EQ(kd_max_depth(c, 1024), 8 + 13);
    c.max_depth = 5;
    EXPECT_EQ(kd_max_depth(c, 1024), 5);
}

TEST(KdNode, PacksALeafOrAPlaneIntoEightBytes) {
    const KdNode empty;
    EXPECT_TRUE(empty.is_leaf() && empty.is_empty_leaf());
    EXPECT_EQ(empty.count(), 0u);
    KdNode leaf = KdNode::leaf(123456, KdNode::kMaxIndex);
    EXPECT_TRUE(leaf.is_leaf());
    EXPECT_FALSE(leaf.is_empty_leaf());
    EXPECT_EQ(leaf.first(), 123456u);
    EXPECT_EQ(leaf.count(), KdNode::kMaxIndex);
    leaf.set_first(0xFFFFFFFFu);  // a leaf's first index has all 32 bits
    EXPECT_EQ(leaf.first(), 0xFFFFFFFFu);
    EXPECT_EQ(leaf.count(), KdNode::kMaxIndex);
    EXPECT_TRUE(KdNode::leaf(7, 0).is_empty_leaf());
    for (int axis = 0; axis < 3; ++axis)
        for (const float split : {-0.0f, 1.5f, -3.25e-30f, 7e30f, std::nextafter(1.0f, 2.0f)}) {
            KdNode n = KdNode::interior(axis, split, KdNode::kMaxIndex - 1);
            EXPECT_FALSE(n.is_leaf());
            EXPECT_FALSE(n.is_empty_leaf());
            EXPECT_EQ(n.axis(), axis);
            EXPECT_EQ(std::bit_cast<uint32_t>(n.split()), std::bit_cast<uint32_t>(split)) << "every bit of the plane";
            EXPECT_EQ(n.lower_child(), KdNode::kMaxIndex - 1);
            EXPECT_EQ(n.upper_child(), KdNode::kMaxIndex);
            EXPECT_EQ(n.count(), 0u);
            n.set_first(5);
            EXPECT_EQ(n.first(), 5u);
            EXPECT_EQ(n.axis(), axis);
            EXPECT_EQ(n.split(), split);
        }
}

TEST(KdTree, BuildIsDeterministic) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 10);
    const KdTree a = build(scene.mesh, KdConfig{}), b = build(scene.mesh, KdConfig{});
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        EXPECT_EQ(a.nodes[i].split(), b.nodes[i].split());
        EXPECT_EQ(a.nodes[i].first(), b.nodes[i].first());
    }
    EXPECT_EQ(a.prim_ids, b.prim_ids);
}

TEST(KdTree, ParallelBuildIsTheSameOnAnyNumberOfThreads) {
    // Big enough that subtrees are built in parallel.
    const SceneCase& scene = scene_case("builtin:soup?n=30000&seed=4", 10);
    const KdTree many = build(scene.mesh, KdConfig{});
    KdTree one;
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        one = build(scene.mesh, KdConfig{});
    }
    ASSERT_EQ(many.nodes.size(), one.nodes.size());
    for (size_t i = 0; i < many.nodes.size(); ++i) {
        EXPECT_EQ(many.nodes[i].split(), one.nodes[i].split());
        EXPECT_EQ(many.nodes[i].first(), one.nodes[i].first());
        EXPECT_EQ(many.nodes[i].count(), one.nodes[i].count());
    }
    EXPECT_EQ(many.prim_ids, one.prim_ids);
    EXPECT_EQ(many.build_stats.leaves, one.build_stats.leaves);
}

TEST(KdTree, TheSahTreesOfTwoScenesArePinned) {
    // A change meant to make the build faster, not different (how the sweep gets its
    // sorted bounds, what runs in parallel), must leave these trees as they are: the
    // counts and the SAH cost to the last bit. A change to the tree itself updates them
    // and says why. The soup's top nodes make their lists and sweeps in parallel.
    struct Pin {
        const char* scene;
        size_t nodes, references, leaves;
        uint32_t max_depth;
        double sah_cost;
    };
    for (const Pin& pin : {Pin{"builtin:teapot", 1537, 7785, 769, 20, 51.495292221066116},
                           Pin{"builtin:soup?n=10000&seed=3", 1895, 13211, 948, 13, 109.09049198753311}}) {
        SCOPED_TRACE(pin.scene);
        const SceneCase& scene = scene_case(pin.scene, 10);
        const KdTree tree = build(scene.mesh, KdConfig{});
        EXPECT_EQ(tree.nodes.size(), pin.nodes);
        EXPECT_EQ(tree.prim_ids.size(), pin.references);
        EXPECT_EQ(tree.build_stats.leaves, pin.leaves);
        EXPECT_EQ(tree.build_stats.max_depth, pin.max_depth);
        EXPECT_EQ(tree.build_stats.sah_cost, pin.sah_cost);
    }
}

TEST(KdTree, MailboxSavesTestsWithoutChangingAnswers) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 2000);
    KdConfig on, off;
    on.mailbox = true;
    off.mailbox = false;
    const KdTree t_on = build(scene.mesh, on), t_off = build(scene.mesh, off);
    Counters c_on, c_off;
    for (const Ray& r : scene.rays) {
        CountingObserver a, b;
        EXPECT_TRUE(same_hit(t_on.intersect_closest(r, a), t_off.intersect_closest(r, b)));
        c_on += a.counters;
        c_off += b.counters;
    }
    EXPECT_GT(c_on.mailbox_skips, 0u);
    EXPECT_EQ(c_on.triangle_tests + c_on.mailbox_skips, c_off.triangle_tests);
}

TEST(KdTree, DegenerateRaysAreAnsweredLikeBruteForce) {
    for (const char* source : {"builtin:soup?n=2000&seed=3", "builtin:single", "builtin:empty", "builtin:cornell"}) {
        const SceneCase& scene = scene_case(source, 10);
        for (const auto& [label, config] : configs())
            expect_degenerate_rays_answered(build(scene.mesh, config), scene.mesh, std::string("kd ") + label + " on " + source);
    }
}

TEST(KdTree, OriginsOnSplitPlanes) {
    for (const char* source : {"builtin:soup?n=2000&seed=3", "builtin:cornell", "builtin:stadium"}) {
        const SceneCase& scene = scene_case(source, 10);
        for (const auto& [label, config] : configs()) {
            const KdTree t = build(scene.mesh, config);
            std::array<std::vector<float>, 3> planes;
            for (const KdNode& n : t.nodes)
                if (!n.is_leaf()) planes[n.axis()].push_back(n.split());
            const SceneCase on_planes = rays_on_planes(scene.mesh, planes, 20000, 12);
            expect_exact(t, on_planes, "kd " + label + " origins on split planes");
        }
    }
}

TEST(KdTree, SmallNodesChooseBySweepsPlaneWhenCounting) {
    // Small nodes find their plane by counting instead of sorting: the same plane
    // (axis, position, cost) as the sweep's first cheapest, on boxes with shared
    // bounds (ties), bounds on the node's faces, and flat boxes.
    Rng rng(20261205);
    // The node straddles 0 on every axis: candidates at -0 and +0 lie inside it.
    const Aabb node{{-2, -1, -0.5f}, {2, 1, 0.5f}};
    KdConfig config;
    std::vector<float> los, his;
    SortScratch scratch;
    for (int trial = 0; trial < 3000; ++trial) {
        const size_t n = 1 + rng.below(kKdCountingMax);
        // Coarse positions make shared bounds likely; some stay on the faces.
        const SpatialRefs refs = lattice_refs(rng, node, n, 8, 0.0f, trial % 7 == 0);
        config.empty_bonus = trial % 2 ? 0.2f : 0.0f;
        KdPlane swept;
        sweep_kd_sah(refs, node, config, los, his, scratch, [&](int a, float s, size_t, size_t, double cost) {
            if (cost < swept.cost) swept = {a, s, cost};
        });
        const KdPlane counted = kd_cheapest_plane_by_counting(refs, node, config);
        ASSERT_EQ(counted.axis, swept.axis) << "trial " << trial;
        ASSERT_EQ(std::bit_cast<uint32_t>(counted.position), std::bit_cast<uint32_t>(swept.position))
            << "trial " << trial << ": the same bits, +0 for a plane at zero";
        ASSERT_EQ(counted.cost, swept.cost) << "trial " << trial;
    }
}

TEST(KdTree, TheBuildersSweepKeepsTheFirstCheapestOfTheWholeSweep) {
    // The builder visits only candidates that may be cheaper than every earlier one
    // (kCheaperOnly: the division skipped where the area sum is no lower): its first
    // cheapest must be the whole sweep's, bit for bit, with ties (lattice bounds, four
    // lanes making equal test counts), the empty-side bonus and one or four lanes.
    Rng rng(29);
    const Aabb node{{-2, -1, -0.5f}, {2, 1, 0.5f}};
    std::vector<float> los, his;
    SortScratch scratch;
    for (int trial = 0; trial < 2000; ++trial) {
        KdConfig config;
        config.empty_bonus = trial % 2 ? 0.2f : 0.0f;
        config.leaf_lanes = trial % 4 < 2 ? 4 : 1;
        const size_t n = 1 + rng.below(trial % 3 == 0 ? 300 : 40);
        const SpatialRefs refs = lattice_refs(rng, node, n, trial % 5 == 0 ? 4 : 16, 0.5f, trial % 7 == 0);
        for (int a = 0; a < 3; ++a) {
            los.resize(n);
            his.resize(n);
            for (size_t i = 0; i < n; ++i) {
                los[i] = refs[i].box.lo[a];
                his[i] = refs[i].box.hi[a];
            }
            sort_ascending(los, scratch);
            sort_ascending(his, scratch);
            KdPlane every, cheaper_only;
            size_t visited_every = 0, visited_cheaper = 0;
            const auto keep = [&](KdPlane& best, size_t& visited) {
                return [&](int axis, float s, size_t, size_t, double cost) {
                    ++visited;
                    if (cost < best.cost) best = {axis, s, cost};
                };
            };
            sweep_sorted_kd_sah_axis<false>(los, his, node, config, a, keep(every, visited_every), [] { return false; });
            sweep_sorted_kd_sah_axis<true>(los, his, node, config, a, keep(cheaper_only, visited_cheaper),
                                           [] { return false; });
            ASSERT_EQ(cheaper_only.axis, every.axis) << "trial " << trial;
            ASSERT_EQ(std::bit_cast<uint32_t>(cheaper_only.position), std::bit_cast<uint32_t>(every.position))
                << "trial " << trial;
            ASSERT_EQ(cheaper_only.cost, every.cost) << "trial " << trial;
            ASSERT_LE(visited_cheaper, visited_every);
        }
    }
}

TEST(KdTree, SweepVisitsEveryBoundInsideOnceWithItsCounts) {
    // The sweep against its definition: every distinct bound strictly inside
    // the node once, in increasing order, with below = #{lo < s}, above = #{hi > s}
    // counted directly. Coarse positions make ties (and both zeros) common.
    Rng rng(23);
    const Aabb node{{-2, -1, -0.5f}, {2, 1, 0.5f}};
    KdConfig config;
    std::vector<float> los, his;
    SortScratch scratch;
    for (int trial = 0; trial < 300; ++trial) {
        const size_t n = trial == 0 ? 3000 : 1 + rng.below(trial % 3 == 0 ? 400 : 40);
        const uint32_t steps = trial % 2 ? 16 : 1u << 20;
        const SpatialRefs refs = lattice_refs(rng, node, n, steps, 0.5f, false);
        for (int a = 0; a < 3; ++a) {
            std::vector<float> expected;
            for (const SpatialRef& r : refs)
                for (float v : {r.box.lo[a] + 0.0f, r.box.hi[a] + 0.0f})
                    if (v > node.lo[a] && v < node.hi[a]) expected.push_back(v);
            std::sort(expected.begin(), expected.end());
            expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
            std::vector<float> visited;
            const auto check = [&](int axis, float s, size_t below, size_t above, double cost) {
                ASSERT_EQ(axis, a);
                size_t want_below = 0, want_above = 0;
                for (const SpatialRef& r : refs) {
                    want_below += r.box.lo[a] < s;
                    want_above += r.box.hi[a] > s;
                }
                ASSERT_EQ(below, want_below) << "trial " << trial << " s " << s;
                ASSERT_EQ(above, want_above) << "trial " << trial << " s " << s;
                ASSERT_EQ(cost, kd_split_cost(config, node, a, s, want_below, want_above, kd_cross_section(node, a),
                                              kd_perimeter_half(node, a), kd_area(node)));
                visited.push_back(s);
            };
            sweep_kd_sah_axis(refs, node, config, a, los, his, scratch, check);
            ASSERT_EQ(visited.size(), expected.size()) << "trial " << trial << " axis " << a;
            for (size_t k = 0; k < visited.size(); ++k)
                ASSERT_EQ(std::bit_cast<uint32_t>(visited[k]), std::bit_cast<uint32_t>(expected[k]))
                    << "trial " << trial << " axis " << a;
        }
    }
}
