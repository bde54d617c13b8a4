#pragma once
/// The octree (lecture: 其他空间划分方法, Oct-Tree): a cell is cut at its centre
/// into eight octants until it holds at most `leaf_size` triangles or reaches
/// `max_depth`. A triangle goes into every octant it comes near, like the KD
/// tree's straddling triangles, and the traversal is the KD tree's with three
/// planes per node: the ray's interval in a node is cut at its crossings of the
/// three centre planes, which orders the (at most four) octants it passes
/// through front to back. Same events and the same in-cell rule (CellHits).

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

/// The deepest an octree may get (root = 0). Traversal pushes at most three
/// octants per level, so its stack holds 3 · kOctreeMaxDepth + 1 entries.
inline constexpr int kOctreeMaxDepth = 20;
inline constexpr int kOctreeStackSize = 3 * kOctreeMaxDepth + 4;

struct OctreeConfig {
    int max_depth = 10;       ///< 1..kOctreeMaxDepth; cells at depth d are 2^-d of the root per axis
    int leaf_size = 8;        ///< a cell with at most this many references is not split, >= 1
    ClipMode clip = ClipMode::Exact;  ///< which octants a straddling triangle goes to (OctantSplit)
    bool mailbox = true;      ///< skip triangles this ray already tested in an earlier cell
    double max_duplication = 64.0;  ///< stop splitting once references exceed this · N (reported), >= 1

    bool operator==(const OctreeConfig&) const = default;
};

std::optional<Error> validate(const OctreeConfig& config);

/// One node, 24 bytes. Invariant: a leaf iff leaf; its triangles are
/// prim_ids[first .. first+count). Otherwise its eight children are
/// nodes[first + o] for octant o = x_high | y_high << 1 | z_high << 2 of the
/// cell cut at `centre` (the centre of its box).
struct OctreeNode {
    /// The tree keeps one copy of each triangle (PartitionTree): its leaves reference a
    /// triangle several times as often as the KD tree's do (docs/performance.md).
    static constexpr bool kOneCopyPerTriangle = true;

    Vec3 centre;
    uint32_t first = 0;
    uint32_t count = 0;
    bool leaf = true;

    bool is_leaf() const { return leaf; }
};

struct OctreeBuildStats : PartitionStats {};

/// An octree over a mesh's triangles (invariants: PartitionTree's): a cell splits
/// at its centre into eight until few triangles remain.
struct Octree : PartitionTree<OctreeNode, OctreeConfig, OctreeBuildStats>, CellQueries<Octree> {
    static constexpr AccelType kType = AccelType::Octree;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const;
    nlohmann::json stats() const;

    /// The box of every node, by index. Nodes store only their centres: the root's box
    /// is `bounds`, and child o's is octant_box(parent's box, parent's centre, o). What
    /// the stepper and the structure overlay draw.
    std::vector<Aabb> node_boxes() const;

private:
    friend struct CellQueries<Octree>;
    /// The walk (CellQueries: intersect_closest, intersect_any), with the triangle test
    /// chosen at compile time. Events: BoxTest (root), VisitNode, SplitPlane (three per
    /// interior node), Push, Pop, Cull, Leaf, TriangleTest, MailboxSkip,
    /// HitOutsideCell, NewClosest, Done.
    template <TriangleTestKind kTest, StopAt kStop, class Observer>
    Hit front_to_back(const Ray& ray, Observer& obs) const;
};

/// The box of octant `o` of `box` cut at `centre`.
inline Aabb octant_box(const Aabb& box, Vec3 centre, int o) {
    Aabb b = box;
    for (int a = 0; a < 3; ++a) {
        if (o >> a & 1) b.lo[a] = centre[a];
        else b.hi[a] = centre[a];
    }
    return b;
}

/// Builds the octree as the KD tree: its top one cell at a time (a big cell's split spread
/// over the threads), then the subtrees below in parallel.
/// `progress` (PartitionProgress's units) may cancel the build: it then returns
/// WorkProgress::cancelled_error().
Expected<Octree> build_octree(const Mesh& mesh, const OctreeConfig& config, WorkProgress* progress = nullptr);

// ---------------------------------------------------------------------------
// Front-to-back traversal.
// ---------------------------------------------------------------------------

template <TriangleTestKind kTest, StopAt kStop, class Observer>
Hit Octree::front_to_back(const Ray& ray, Observer& obs) const {
    using Hits = CellHits<kTest, kStop>;
    const RayPrecomp pre(ray);
    CellWalk<kOctreeStackSize> walk;
    using Entry = CellWalk<kOctreeStackSize>::Entry;
    Entry cur;
    if (nodes.empty() || !walk.start(bounds, pre, ray, cur, obs)) return Hits::missed(obs);
    Hits hits(ray, pre, triangles, corners, build_config.mailbox, /*strict_cell=*/true, build_stats.triangles);
    do {
        walk.visit(cur, obs);
        const OctreeNode* n = &nodes[cur.node];
        while (!n->is_leaf()) {
            // Where the ray crosses each centre plane, and which side it starts on.
            float t_cross[3];
            int octant = 0;
            for (int a = 0; a < 3; ++a) {
                const float d = ray.dir[a];
                bool high;
                if (d == 0.0f) {
                    t_cross[a] = kInfinity;  // never crosses; on the plane either side is right (padding)
                    high = ray.origin[a] >= n->centre[a];
                } else {
                    t_cross[a] = (n->centre[a] - ray.origin[a]) * pre.dir_inv[a];
                    // Moving up it is high once it has crossed; moving down, until it crosses.
                    high = d > 0.0f ? t_cross[a] <= cur.t_min : t_cross[a] > cur.t_min;
                }
                if (high) octant |= 1 << a;
                obs.on({.kind = EventKind::SplitPlane, .axis = uint8_t(a), .near_first = !high, .node = cur.node,
                        .t = t_cross[a], .split = n->centre[a]});
            }
            // The crossings inside the interval, in order; each flips one octant bit.
            int order[3] = {0, 1, 2};
            if (t_cross[order[1]] < t_cross[order[0]]) std::swap(order[0], order[1]);
            if (t_cross[order[2]] < t_cross[order[1]]) std::swap(order[1], order[2]);
            if (t_cross[order[1]] < t_cross[order[0]]) std::swap(order[0], order[1]);
            Entry segments[4];
            int count = 0;
            float t = cur.t_min;
            for (int i = 0; i < 3; ++i) {
                const int a = order[i];
                if (!(t_cross[a] > cur.t_min && t_cross[a] < cur.t_max)) continue;  // also drops NaN
                segments[count++] = {n->first + uint32_t(octant), t, t_cross[a]};
                t = t_cross[a];
                octant ^= 1 << a;
            }
            segments[count++] = {n->first + uint32_t(octant), t, cur.t_max};
            // Farthest first onto the stack, skipping empty cells; go on with the nearest non-empty one.
            bool have_next = false;
            for (int i = count - 1; i >= 0; --i) {
                const OctreeNode& child = nodes[segments[i].node];
                if (child.is_leaf() && child.count == 0) continue;
                if (have_next) walk.push(cur, obs);
                cur = segments[i];
                have_next = true;
            }
            if (!have_next) break;  // every octant on the ray's path is empty
            walk.visit(cur, obs);
            n = &nodes[cur.node];
        }
        if (n->is_leaf() && walk.template test_leaf<kOneCopyPerTriangle>(cur, n->first, n->count, prim_ids.data(), copy_index.data(), hits, obs)) break;
    } while (walk.pop_next(hits, cur, obs));
    return hits.done(obs);
}

}  // namespace accelviz
