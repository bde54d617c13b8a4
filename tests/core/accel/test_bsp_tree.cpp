// The BSP tree: exact against brute force (rays of every kind, origins on its
// tilted planes, degenerate rays), front-to-back order, and its invariants.
#include <gtest/gtest.h>

#include "accel/space_partition_support.h"
#include "core/accel/bsp_tree.h"

using namespace accelviz;
using namespace accelviz::test;

namespace {

BspTree build(const Mesh& mesh, BspConfig config) {
    auto tree = build_bsp_tree(mesh, config);
    if (!tree.ok()) throw std::runtime_error(tree.error());
    return std::move(*tree);
}

std::vector<std::pair<std::string, BspConfig>> configs() {
    std::vector<std::pair<std::string, BspConfig>> out;
    out.push_back({"default", BspConfig{}});
    BspConfig few;
    few.candidates = 2;
    few.mailbox = false;
    out.push_back({"candidates=2 mailbox=off", few});
    BspConfig fine;
    fine.leaf_size = 1;
    fine.max_depth = 30;
    out.push_back({"leaf=1 depth=30", fine});
    return out;
}

void check_scene(const std::string& source) {
    const SceneCase& scene = scene_case(source);
    for (const auto& [label, config] : configs()) {
        const BspTree tree = build(scene.mesh, config);
        expect_exact(tree, scene, "bsp " + label);
        expect_trace_agrees(tree, scene, 97, "bsp " + label);
    }
}

/// Every node with the half-spaces that make its cell (plane, back side?).
struct NodeCell {
    uint32_t node;
    std::vector<std::pair<Plane, bool>> sides;
};
std::vector<NodeCell> node_cells(const BspTree& t) {
    std::vector<NodeCell> out;
    if (t.nodes.empty()) return out;
    std::vector<NodeCell> stack{{0, {}}};
    while (!stack.empty()) {
        NodeCell c = std::move(stack.back());
        stack.pop_back();
        const BspNode& n = t.nodes[c.node];
        if (!n.is_leaf()) {
            for (int side = 0; side < 2; ++side) {
                NodeCell child{n.first + uint32_t(side), c.sides};
                child.sides.push_back({n.plane, side == 0});
                stack.push_back(std::move(child));
            }
        }
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace

TEST(BspTree, ExactOnStadium) { check_scene("builtin:stadium"); }
TEST(BspTree, ExactOnSameBox) { check_scene("builtin:same-box"); }
TEST(BspTree, ExactOnSameCentroid) { check_scene("builtin:same-centroid"); }
TEST(BspTree, ExactOnSoup) { check_scene("builtin:soup?n=2000&seed=3"); }
TEST(BspTree, ExactOnEmptyScene) { check_scene("builtin:empty"); }
TEST(BspTree, ExactOnSingleTriangle) { check_scene("builtin:single"); }
TEST(BspTree, ExactOnCornellBox) { check_scene("builtin:cornell"); }
TEST(BspTree, ExactOnTeapot) { check_scene("builtin:teapot"); }
TEST(BspTree, SlowExactOnBunny) {
    if (!shared_asset_exists("bunny.obj")) GTEST_SKIP() << "../shared/assets/bunny.obj is not here";
    check_scene("bunny");
}

TEST(BspTree, SplitsByTrianglePlanesWhereTheyPay) {
    // The teapot's surface bends both ways: many of its triangles' planes cut it.
    const BspTree teapot = build(scene_case("builtin:teapot", 10).mesh, BspConfig{});
    EXPECT_GT(teapot.build_stats.triangle_planes, 0u);
    size_t tilted = 0;
    for (const BspNode& n : teapot.nodes)
        if (!n.is_leaf() && n.from_triangle) {
            const Vec3 a = n.plane.normal;
            EXPECT_NEAR(length(a), 1.0f, 1e-5f);
            if (std::abs(a.x) < 0.99f && std::abs(a.y) < 0.99f && std::abs(a.z) < 0.99f) ++tilted;
        }
    EXPECT_GT(tilted, 0u) << "planes that face any way, not only the axes";
    // Planes of either kind are counted, and add up to the interior nodes.
    EXPECT_GT(teapot.build_stats.axis_planes, 0u);
    EXPECT_EQ(teapot.build_stats.triangle_planes + teapot.build_stats.axis_planes,
              teapot.build_stats.nodes - teapot.build_stats.leaves);
}

TEST(BspTree, LeavesAreVisitedFrontToBack) {
    const SceneCase& scene = scene_case("builtin:soup?n=2000&seed=3", 1000);
    const BspTree t = build(scene.mesh, BspConfig{});
    for (const Ray& r : scene.rays) {
        RecordingObserver rec;
        t.intersect_closest(r, rec);
        float last = -kInfinity;
        for (const auto& e : rec.events)
            if (e.kind == EventKind::Leaf) {
                EXPECT_GE(e.t_enter, last);
                EXPECT_LE(e.t_enter, e.t_exit);
                last = e.t_exit;
            }
    }
}

TEST(BspTree, EveryLeafHoldsEveryTriangleThatReachesItsCell) {
    // Sample points of each triangle (corners, edge midpoints, centroid, and a grid
    // of barycentric points): one inside a leaf's cell (by more than half the
    // padding) means the leaf must list the triangle.
    const SceneCase& scene = scene_case("builtin:soup?n=400&seed=9", 10);
    const BspTree t = build(scene.mesh, BspConfig{});
    const float margin = 0.5f * t.build_stats.padding;
    size_t missing = 0, leaves = 0;
    for (const NodeCell& c : node_cells(t)) {
        const BspNode& n = t.nodes[c.node];
        if (!n.is_leaf()) continue;
        ++leaves;
        std::vector<char> here(scene.mesh.triangle_count(), 0);
        for (uint32_t k = n.first; k < n.first + n.count; ++k) here[t.prim_ids[k]] = 1;
        for (uint32_t tri = 0; tri < scene.mesh.triangle_count(); ++tri) {
            if (here[tri]) continue;
            const Vec3 p0 = scene.mesh.vertex(tri, 0), p1 = scene.mesh.vertex(tri, 1), p2 = scene.mesh.vertex(tri, 2);
            for (int i = 0; i <= 6; ++i)
                for (int j = 0; i + j <= 6; ++j) {
                    const float u = i / 6.0f, v = j / 6.0f;
                    const Vec3 p = p0 + (p1 - p0) * u + (p2 - p0) * v;
                    bool inside = t.bounds.contains(p);
                    for (const auto& [plane, back] : c.sides)
                        inside = inside && (back ? plane.distance(p) < -margin : plane.distance(p) > margin);
                    if (inside) ++missing;
                }
        }
    }
    EXPECT_EQ(missing, 0u);
    EXPECT_EQ(leaves, t.build_stats.leaves);
    EXPECT_EQ(t.nodes.size(), 2 * leaves - 1);
}

TEST(BspTree, DegenerateRaysAreAnsweredLikeBruteForce) {
    for (const char* source : {"builtin:soup?n=2000&seed=3", "builtin:single", "builtin:empty", "builtin:cornell"}) {
        const SceneCase& scene = scene_case(source, 10);
        for (const auto& [label, config] : configs())
            expect_degenerate_rays_answered(build(scene.mesh, config), scene.mesh,
                                            std::string("bsp ") + label + " on " + source);
    }
}

TEST(BspTree, OriginsOnItsTiltedPlanes) {
    // Rays that start on a node's plane, inside its cell: moving within the plane,
    // and through it either way.
    for (const char* source : {"builtin:teapot", "builtin:soup?n=2000&seed=3", "builtin:cornell"}) {
        const SceneCase& scene = scene_case(source, 10);
        const BspTree t = build(scene.mesh, BspConfig{});
        const BspTree::NodeShapes& shapes = t.node_shapes();
        SceneCase on_planes;
        on_planes.mesh = scene.mesh;
        Rng rng(31);
        for (size_t i = 0; i < t.nodes.size() && on_planes.rays.size() < 20000; ++i) {
            const Polygon& poly = shapes.split_polygons[i];
            if (poly.size() < 3) continue;
            const Vec3 n = t.nodes[i].plane.normal;
            for (int k = 0; k < 12; ++k) {
                // A point inside the polygon: a random convex combination of its corners.
                Vec3 p{0, 0, 0};
                float total = 0;
                for (const Vec3& c : poly) {
                    const float w = rng.uniform(0.0f, 1.0f);
                    p = p + c * w;
                    total += w;
                }
                p = p / total;
                Vec3 d = random_direction(rng);
                if (k % 3 == 0) d = normalize(d - n * dot(d, n));  // along the plane
                on_planes.rays.push_back({p, d});
            }
        }
        on_planes.answers = brute_force_answers(on_planes.mesh, on_planes.rays);
        expect_exact(t, on_planes, std::string("bsp origins on its planes, ") + source);
    }
}

TEST(BspTree, CellShapesContainTheirChildrenAndThePlanesLieInTheirCells) {
    const BspTree t = build(scene_case("builtin:teapot", 10).mesh, BspConfig{});
    const BspTree::NodeShapes& shapes = t.node_shapes();
    ASSERT_EQ(shapes.cell_bounds.size(), t.nodes.size());
    EXPECT_EQ(shapes.cell_bounds[0], t.bounds);
    const float eps = 1e-4f * length(t.bounds.extent());
    size_t drawn = 0;
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        const BspNode& n = t.nodes[i];
        if (n.is_leaf()) {
            EXPECT_TRUE(shapes.split_polygons[i].empty());
            continue;
        }
        const Aabb outer = padded(shapes.cell_bounds[i], eps);
        for (int side = 0; side < 2; ++side)
            EXPECT_TRUE(outer.contains(shapes.cell_bounds[n.first + uint32_t(side)])) << i;
        for (const Vec3& p : shapes.split_polygons[i]) {
            EXPECT_TRUE(outer.contains(p)) << i;
            EXPECT_NEAR(n.plane.distance(p), 0.0f, eps) << i;
        }
        drawn += shapes.split_polygons[i].size() >= 3;
    }
    EXPECT_GT(drawn, 0u);
}

TEST(BspTree, BadConfigIsAnErrorNamingTheFlag) {
    const Mesh& mesh = scene_case("builtin:single", 10).mesh;
    auto deep = build_bsp_tree(mesh, BspConfig{.max_depth = 0});
    ASSERT_FALSE(deep.ok());
    EXPECT_NE(deep.error().find("--bsp-max-depth"), std::string::npos);
    auto none = build_bsp_tree(mesh, BspConfig{.candidates = 0});
    ASSERT_FALSE(none.ok());
    EXPECT_NE(none.error().find("--bsp-candidates"), std::string::npos);
}

namespace {

/// The teapot with every coordinate times `scale` plus `offset`, its rays and brute force's answers.
SceneCase moved_teapot(float scale, float offset) {
    SceneCase c;
    c.mesh = scene_case("builtin:teapot", 10).mesh;
    for (Vec3& p : c.mesh.positions) p = p * scale + Vec3{offset, offset, offset};
    c.rays = make_test_rays(c.mesh, 20000, 5);
    c.answers = brute_force_answers(c.mesh, c.rays);
    return c;
}

/// Every interior node's plane cuts its cell (a polygon with corners) and no cell is
/// empty: a plane that missed its cell would make one of no volume.
void expect_planes_cut_their_cells(const BspTree& t, const std::string& label) {
    const BspTree::NodeShapes& shapes = t.node_shapes();
    ASSERT_EQ(shapes.cell_bounds.size(), t.nodes.size()) << label;
    size_t missed = 0, empty = 0;
    for (size_t i = 0; i < t.nodes.size(); ++i) {
        if (!t.nodes[i].is_leaf() && shapes.split_polygons[i].size() < 3) ++missed;
        if (shapes.cell_bounds[i].empty()) ++empty;
    }
    EXPECT_EQ(missed, 0u) << label;
    EXPECT_EQ(empty, 0u) << label;
}

}  // namespace

TEST(BspTree, TheTreeDoesNotDependOnTheSceneUnits) {
    // The same teapot in micrometres or kilometres: the same tree, give or take rounding.
    const SceneCase one = moved_teapot(1.0f, 0.0f);
    const BspTree reference = build(one.mesh, BspConfig{});
    expect_planes_cut_their_cells(reference, "x1");
    for (const float scale : {1e-6f, 1e-3f, 1e3f}) {
        const SceneCase scaled = moved_teapot(scale, 0.0f);
        const BspTree t = build(scaled.mesh, BspConfig{});
        const std::string label = "scale " + std::to_string(scale);
        EXPECT_NEAR(double(t.nodes.size()), double(reference.nodes.size()), 0.03 * double(reference.nodes.size()))
            << label;
        expect_planes_cut_their_cells(t, label);
        // (The test rays start at least 1e-3 from the scene: for the micro-teapot
        // that is hundreds of its sizes away, beyond the structures' stated precision.)
        if (scale >= 1e-3f) expect_exact(t, scaled, "bsp " + label);
    }
}

TEST(BspTree, FarFromTheOriginItsPlanesStillCutTheirCells) {
    // At 3000 the padding (a fraction of the coordinates' size) is large against the
    // teapot: few planes can cut, and none may be taken that does not.
    const SceneCase far = moved_teapot(1.0f, 3000.0f);
    const BspTree t = build(far.mesh, BspConfig{});
    expect_planes_cut_their_cells(t, "offset 3000");
    EXPECT_LT(t.build_stats.duplication, 16.0) << "no cells of no volume filling the budget";
    expect_exact(t, far, "bsp offset 3000");
}
