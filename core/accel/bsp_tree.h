#pragma once
/// The BSP tree (lecture: 其他空间划分方法, "BSP 树: 用任意平面递归地划分空间"):
/// like the KD tree, but a node's plane may face any way. The planes are the
/// mesh's own triangle planes (the autopartition of Fuchs, Kedem & Naylor 1980,
/// "On visible surface generation by a priori tree structures") and, competing
/// with them, axis-aligned planes, as Ize, Wald & Parker 2008 ("Ray tracing with
/// the BSP tree") mix both kinds: the planes of an even sample of the node's
/// triangles, and on each axis the middle and the two ends of what the node holds
/// (a cut there leaves empty space). The cheapest by the lecture's SAH wins, with
/// the cells' true surface areas (of their polyhedra), or the node stays a leaf.
/// (A triangle's plane cannot cut a convex piece of surface: every other triangle
/// of it lies behind. So on a smooth scan most planes end up axis-aligned.)
///
/// A cell is a convex polyhedron, not a box; a triangle is kept in a child if the
/// part of it in its parent's cell (a polygon, clipped plane by plane) comes
/// within `padding` of the child's side. Traversal is the KD tree's front-to-back
/// walk with one general plane per node: t_split = (c - N·o) / (N·d), and the
/// same in-cell rule (CellHits), so the answer is brute force's.

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/accel_type.h"
#include "core/accel/cell_hits.h"
#include "core/accel/cell_walk.h"
#include "core/accel/spatial_refs.h"
#include "core/geometry/mesh.h"
#include "core/util/expected.h"

namespace accelviz {

/// The deepest a BSP tree may get (root = 0); traversal pushes at most one node per level.
inline constexpr int kBspMaxDepth = 60;
inline constexpr int kBspStackSize = kBspMaxDepth + 4;
/// The most triangle planes a node may try (each is weighed against all its triangles).
inline constexpr int kBspMaxCandidates = 4096;

/// The SplitPlane event's `axis` for a general plane (0, 1, 2 are x, y, z): the
/// plane is the node's (BspTree::nodes[node]), `split` its offset c.
inline constexpr uint8_t kGeneralPlane = 3;

struct BspConfig {
    int max_depth = 40;       ///< 1..kBspMaxDepth
    int leaf_size = 2;        ///< a node with at most this many triangles is a leaf, >= 1
    int candidates = 24;      ///< triangle planes tried per node (an even sample of its triangles), >= 1
    float cost_trav = 2.0f;   ///< SAH: C_trav, one node step (as the KD tree's), >= 0
    float cost_isect = 1.0f;  ///< SAH: C_isect, one ray-triangle test, > 0
    float empty_bonus = 0.2f; ///< SAH: a plane that leaves one side empty costs (1 - bonus)·cost
    bool mailbox = true;      ///< skip triangles this ray already tested in an earlier cell
    double max_duplication = 16.0;  ///< stop splitting once references exceed this · N (reported), >= 1

    bool operator==(const BspConfig&) const = default;
};

std::optional<Error> validate(const BspConfig& config);

/// A plane N·p = c; N has unit length. Its back side is N·p < c.
struct Plane {
    Vec3 normal;
    float offset = 0;
    float distance(Vec3 p) const { return dot(normal, p) - offset; }
};

/// One node, 28 bytes. A leaf iff leaf; its triangles are prim_ids[first ..
/// first+count). Otherwise its back child (N·p < c) is nodes[first], its front
/// child nodes[first + 1].
struct BspNode {
    Plane plane;
    uint32_t first = 0;
    uint32_t count = 0;
    bool leaf = true;
    bool from_triangle = false;  ///< the plane is a triangle's (else an axis-aligned one)

    bool is_leaf() const { return leaf; }
    bool is_empty_leaf() const { return leaf && count == 0; }
};

struct BspBuildStats : PartitionStats {
    uint32_t triangle_planes = 0;  ///< interior nodes split by a triangle's plane
    uint32_t axis_planes = 0;      ///< ... by an axis-aligned plane
};

/// A convex polygon (a node's split plane inside its cell, a cell's face).
using Polygon = std::vector<Vec3>;

/// The part of convex `polygon` on the back side of `plane` (`back` true) or its
/// front side, grown by `pad` (Sutherland–Hodgman against one plane).
Polygon clip_polygon(const Polygon& polygon, const Plane& plane, bool back, float pad = 0.0f);

/// A BSP tree over a mesh's triangles (invariants: PartitionTree's; `bounds`, the
/// root's cell, is the scene's box grown by the padding).
struct BspTree : PartitionTree<BspNode, BspConfig, BspBuildStats>, CellQueries<BspTree> {
    static constexpr AccelType kType = AccelType::Bsp;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const;
    nlohmann::json stats() const;

    /// What the overlay and the stepper draw, by node, kept from the build (which
    /// cuts each cell's faces anyway): the bounds of its cell (a convex polyhedron:
    /// the root's box cut by its ancestors' planes), and for an interior node its
    /// plane inside the cell (the polygon the cut makes; empty for a leaf).
    struct NodeShapes {
        std::vector<Aabb> cell_bounds;
        std::vector<Polygon> split_polygons;
    };
    NodeShapes shapes;
    const NodeShapes& node_shapes() const { return shapes; }

private:
    friend struct CellQueries<BspTree>;
    /// The walk (CellQueries: intersect_closest, intersect_any), with the triangle
    /// test chosen at compile time. Events: BoxTest (root), VisitNode, SplitPlane
    /// (axis = kGeneralPlane, near_first = the back side first), Push, Pop, Cull,
    /// Leaf, TriangleTest, MailboxSkip, HitOutsideCell, NewClosest, Done.
    template <TriangleTestKind kTest, StopAt kStop, class Observer>
    Hit front_to_back(const Ray& ray, Observer& obs) const;
};

/// Builds the tree depth first on one thread. `progress` (PartitionProgress's
/// units) may cancel it: it then returns WorkProgress::cancelled_error().
Expected<BspTree> build_bsp_tree(const Mesh& mesh, const BspConfig& config, WorkProgress* progress = nullptr);

// ---------------------------------------------------------------------------
// Front-to-back traversal.
// ---------------------------------------------------------------------------

template <TriangleTestKind kTest, StopAt kStop, class Observer>
Hit BspTree::front_to_back(const Ray& ray, Observer& obs) const {
    using Hits = CellHits<kTest, kStop>;
    const RayPrecomp pre(ray);
    CellWalk<kBspStackSize> walk;
    CellWalk<kBspStackSize>::Entry cur;
    if (nodes.empty() || !walk.start(bounds, pre, ray, cur, obs)) return Hits::missed(obs);
    Hits hits(ray, pre, triangles, corners, build_config.mailbox, /*strict_cell=*/true, build_stats.triangles);
    do {
        walk.visit(cur, obs);
        const BspNode* n = &nodes[cur.node];
        while (!n->is_leaf()) {
            const Plane& p = n->plane;
            // In double: N·o - c is a difference of nearly equal numbers for a far origin.
            const double along = double(p.normal.x) * ray.dir.x + double(p.normal.y) * ray.dir.y +
                                 double(p.normal.z) * ray.dir.z;
            const double ahead = double(p.offset) - (double(p.normal.x) * ray.origin.x +
                                                     double(p.normal.y) * ray.origin.y +
                                                     double(p.normal.z) * ray.origin.z);
            const float t_split = float(ahead / along);
            // Moving towards the front (or along the plane, +0), the back side comes
            // first; the sign of t_split then says whether the ray ever crosses.
            const bool back_first = !std::signbit(along);
            const uint32_t near = n->first + (back_first ? 0 : 1), far = n->first + (back_first ? 1 : 0);
            obs.on({.kind = EventKind::SplitPlane, .axis = kGeneralPlane, .near_first = back_first, .node = cur.node,
                    .t = t_split, .split = p.offset});
            walk.cross_plane(cur, t_split, near, far, nodes.data(), obs);
            walk.visit(cur, obs);
            n = &nodes[cur.node];
        }
        if (walk.template test_leaf<kOneCopyPerTriangle>(cur, n->first, n->count, prim_ids.data(), copy_index.data(), hits, obs)) break;
    } while (walk.pop_next(hits, cur, obs));
    return hits.done(obs);
}

}  // namespace accelviz
