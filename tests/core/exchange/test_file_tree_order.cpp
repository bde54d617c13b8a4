// The construction-order view of a tree from a file: node by node, the same node,
// triangles and SAH cost as our builder recorded for the tree it exported; the
// hand-made trees' numbers by hand; broken files (cycles, a node named twice,
// unreachable nodes, ids out of range) walked safely.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/accel/bvh_build.h"
#include "core/accel/factory.h"
#include "core/accel/kd_tree.h"
#include "core/exchange/file_tree_order.h"
#include "core/geometry/scene.h"

namespace accelviz {
namespace {

std::vector<uint32_t> sorted(std::vector<uint32_t> v) {
    std::sort(v.begin(), v.end());
    return v;
}

TEST(FileTreeOrder, OurExportedBvhStepsAsOurBuilderRecordedIt) {
    auto mesh = load_scene("builtin:teapot", MeshCache::Skip);
    ASSERT_TRUE(mesh.ok());
    BvhConfig config;
    config.builder = BvhBuilder::SahBinned;
    BuildRecorder recorder;
    recorder.record_candidates = false;
    auto bvh = build_bvh(*mesh, config, &recorder);
    ASSERT_TRUE(bvh.ok()) << bvh.error();
    auto file = export_structure(AcceleratorFor<Bvh>(*bvh), *mesh, {});
    ASSERT_TRUE(file.ok()) << file.error();
    const FileTreeOrder order = file_tree_order(*file);
    ASSERT_EQ(order.size(), bvh->nodes.size());
    const SahCosts costs{config.cost_trav, config.cost_isect};
    for (const BuildStep& want : recorder.steps) {
        const FileNodeStep got = file_node_step(*file, order, want.node, mesh->triangle_count(), costs);
        SCOPED_TRACE("node " + std::to_string(want.node));
        EXPECT_TRUE(got.reached);
        EXPECT_EQ(got.depth, want.depth);
        EXPECT_EQ(got.triangle_count, want.count);
        EXPECT_EQ(got.box, bvh->nodes[want.node].bounds);
        const auto range = [&](uint32_t begin, uint32_t end) {
            return sorted({bvh->prim_ids.begin() + begin, bvh->prim_ids.begin() + end});
        };
        EXPECT_FLOAT_EQ(got.leaf_cost, want.leaf_cost);
        if (bvh->nodes[want.node].is_leaf()) {
            EXPECT_TRUE(got.leaf);
            ASSERT_EQ(got.triangles.size(), 1u);
            EXPECT_EQ(sorted(got.triangles[0]), range(want.first, want.first + want.count));
            continue;
        }
        EXPECT_FALSE(got.leaf);
        ASSERT_EQ(got.children.size(), 2u);
        EXPECT_EQ(order.parent[got.children[0]], int64_t(want.node));
        EXPECT_EQ(sorted(got.triangles[0]), range(want.first, want.first + want.left_count));
        EXPECT_EQ(sorted(got.triangles[1]), range(want.first + want.left_count, want.first + want.count));
        // The builder's cost of the split it made, with the children's real boxes.
        EXPECT_NEAR(got.split_cost, want.split_cost, 1e-5f * want.split_cost);
    }
}

TEST(FileTreeOrder, OurExportedKdTreeGivesEachChildItsCellAndTriangles) {
    auto mesh = load_scene("builtin:teapot", MeshCache::Skip);
    ASSERT_TRUE(mesh.ok());
    AccelConfig c;
    c.type = AccelType::Kd;
    auto accel = build_accelerator(*mesh, c);
    ASSERT_TRUE(accel.ok()) << accel.error();
    auto file = export_structure(**accel, *mesh, {});
    ASSERT_TRUE(file.ok());
    const FileTreeOrder order = file_tree_order(*file);
    const KdTree& kd = *structure_if<KdTree>(**accel);
    // The root holds every triangle a leaf lists; a child's cell is its parent's cut at the plane.
    std::vector<uint32_t> listed(kd.prim_ids.begin(), kd.prim_ids.end());
    std::sort(listed.begin(), listed.end());
    listed.erase(std::unique(listed.begin(), listed.end()), listed.end());
    const FileNodeStep root = file_node_step(*file, order, 0, mesh->triangle_count(), {});
    EXPECT_EQ(root.triangle_count, listed.size());
    EXPECT_EQ(root.box, kd.bounds);
    ASSERT_FALSE(root.leaf);
    EXPECT_EQ(root.axis, kd.nodes[0].axis());
    Aabb below = kd.bounds, above = kd.bounds;
    below.hi[root.axis] = above.lo[root.axis] = root.split;
    ASSERT_EQ(root.child_boxes.size(), 2u);
    EXPECT_EQ(root.child_boxes[0], below);
    EXPECT_EQ(root.child_boxes[1], above);
    // A triangle straddling the plane is under both children: the two lists together are longer.
    EXPECT_GT(root.triangles[0].size() + root.triangles[1].size(), root.triangle_count);
    // Every node: each child's list holds what that child's subtree leaves list, once each.
    for (uint64_t n = 0; n < order.size(); ++n) {
        const FileNodeStep s = file_node_step(*file, order, n, mesh->triangle_count(), {});
        if (s.leaf) {
            EXPECT_EQ(sorted(s.triangles[0]), sorted(file->kd_nodes[n].triangles)) << "node " << n;
            continue;
        }
        for (size_t k = 0; k < 2; ++k) {
            const FileNodeStep child = file_node_step(*file, order, s.children[k], mesh->triangle_count(), {});
            EXPECT_EQ(child.triangle_count, s.triangles[k].size()) << "node " << n;
            EXPECT_EQ(child.box, s.child_boxes[k]);
            EXPECT_EQ(child.depth, s.depth + 1);
        }
    }
}

/// Four triangles in a row along x (the mesh of the structure-check tests): a root, leaves of two.
Aabb box(float x0, float x1) { return {{x0, 0, 0}, {x1, 1, 0}}; }

StructureFile hand_made_bvh() {
    StructureFile f;
    f.type = AccelType::Bvh;
    f.mesh.triangles = 4;
    f.order = {0, 1, 2, 3};
    f.bvh_nodes = {{box(0, 3.8f), true, {1, 2}, 0, 0}, {box(0, 1.8f), false, {}, 0, 2}, {box(2, 3.8f), false, {}, 2, 2}};
    return f;
}

TEST(FileTreeOrder, TheHandMadeTreesNumbers) {
    const StructureFile f = hand_made_bvh();
    const FileTreeOrder order = file_tree_order(f);
    EXPECT_EQ(order.parent, (std::vector<int64_t>{-1, 0, 0}));
    EXPECT_EQ(order.depth, (std::vector<uint32_t>{0, 1, 1}));
    const FileNodeStep root = file_node_step(f, order, 0, 4, {.trav = 2.0f, .isect = 3.0f});
    EXPECT_FALSE(root.parent.has_value());
    EXPECT_EQ(root.triangles, (std::vector<std::vector<uint32_t>>{{0, 1}, {2, 3}}));
    EXPECT_EQ(root.triangle_count, 4u);
    // Flat boxes: areas 2·1.8 and 2·3.8 (and 2·1.8 for the right child).
    const float p = 1.8f / 3.8f;
    ASSERT_EQ(root.child_probability.size(), 2u);
    EXPECT_FLOAT_EQ(root.child_probability[0], p);
    EXPECT_FLOAT_EQ(root.split_cost, 2.0f + 2 * (p * 2 * 3.0f));
    EXPECT_FLOAT_EQ(root.leaf_cost, 12.0f);
    const FileNodeStep leaf = file_node_step(f, order, 2, 4, {});
    EXPECT_TRUE(leaf.leaf);
    EXPECT_EQ(leaf.parent, 0u);
    EXPECT_EQ(leaf.triangles, (std::vector<std::vector<uint32_t>>{{2, 3}}));
}

TEST(FileTreeOrder, BrokenFilesAreWalkedSafely) {
    // A cycle (node 2 names the root), a node named twice, an unreachable node, a
    // child out of range, a leaf range past "order" and a triangle id past the mesh.
    StructureFile f = hand_made_bvh();
    f.bvh_nodes[2] = {box(2, 3.8f), true, {0, 1, 9}, 0, 0};
    f.bvh_nodes.push_back({box(0, 1), false, {}, 3, 5});
    f.order[1] = 99;
    const FileTreeOrder order = file_tree_order(f);
    EXPECT_EQ(order.reached, (std::vector<uint8_t>{1, 1, 1, 0}));
    const FileNodeStep root = file_node_step(f, order, 0, 4, {});
    ASSERT_EQ(root.children.size(), 2u);
    EXPECT_EQ(root.triangles[0], (std::vector<uint32_t>{0}));  // 99 is not a triangle
    EXPECT_EQ(sorted(root.triangles[1]), (std::vector<uint32_t>{0}));  // through the cycle to node 1
    const FileNodeStep cyclic = file_node_step(f, order, 2, 4, {});
    EXPECT_EQ(cyclic.children, (std::vector<uint64_t>{0, 1}));  // 9 is not a node
    const FileNodeStep lost = file_node_step(f, order, 3, 4, {});
    EXPECT_FALSE(lost.reached);
    EXPECT_EQ(lost.triangles, (std::vector<std::vector<uint32_t>>{{3}}));  // "order" ends at 4
    // More children than a node may have: the first eight are walked.
    StructureFile wide = hand_made_bvh();
    wide.bvh_nodes[0].children.assign(100000, 1);
    const FileNodeStep crowded = file_node_step(wide, file_tree_order(wide), 0, 4, {});
    EXPECT_EQ(crowded.children.size(), 8u);
    EXPECT_EQ(crowded.children_left_out, 100000u - 8u);
    // A KD tree with a cycle, a child naming itself, one out of range and a NaN plane.
    StructureFile kd;
    kd.type = AccelType::Kd;
    kd.bounds = {{0, 0, 0}, {4, 1, 1}};
    FileKdNode top, self, leaf;
    top.axis = 0;
    top.split = 2;
    top.children = {1, 2};
    self.axis = 1;
    self.split = std::nanf("");
    self.children = {1, 0};
    leaf.triangles = {0, 1, 7};
    kd.kd_nodes = {top, self, leaf};
    kd.kd_nodes.push_back(kd.kd_nodes[0]);
    kd.kd_nodes[3].children = {9, 2};
    const FileTreeOrder kd_order = file_tree_order(kd);
    for (uint64_t n = 0; n < kd_order.size(); ++n) {
        const FileNodeStep step = file_node_step(kd, kd_order, n, 4, {});
        EXPECT_EQ(step.node, n);
    }
    EXPECT_EQ(file_node_step(kd, kd_order, 0, 4, {}).triangle_count, 2u) << "7 is not a triangle";
    EXPECT_EQ(file_node_step(kd, kd_order, 3, 4, {}).children, (std::vector<uint64_t>{2})) << "9 is not a node";
    // A grid has no nodes to order.
    StructureFile grid;
    grid.type = AccelType::Grid;
    EXPECT_EQ(file_tree_order(grid).size(), 0u);
}

}  // namespace
}  // namespace accelviz
