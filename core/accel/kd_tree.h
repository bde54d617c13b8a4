#pragma once
/// The KD tree (lecture: KD 树划分): space cut recursively by axis-aligned
/// planes; a triangle that straddles a plane is stored on both sides. Traversal
/// walks the leaves the ray passes through, front to back (内部节点，选择先与光线
/// 相交的分支), with a stack of (node, t_min, t_max).
///
/// The lecture's pitfall (slide "KD 树划分的挑战"): a straddling triangle tested in
/// an early leaf may report a hit that lies in a later leaf, behind a closer
/// triangle there. So a hit counts only inside the current leaf's
/// [t_min, t_max] (CellHits); `strict_cell = false` shows the wrong answers the
/// naive rule gives. Built by build_kd_tree(): median or SAH (Wald & Havran 2006,
/// "On building fast kd-trees for ray tracing, and on doing that in O(N log N)").

#include <bit>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/accel_type.h"
#include "core/accel/cell_hits.h"
#include "core/accel/cell_walk.h"
#include "core/accel/spatial_refs.h"
#include "core/geometry/mesh.h"
#include "core/util/expected.h"

namespace accelviz {

/// How the builder chooses a node's plane.
enum class KdBuilder : uint8_t {
    Median,  ///< the spatial median (middle) of the node's longest axis; the next axis if that separates nothing
    Sah,     ///< the cheapest plane by the SAH among every reference-box boundary on all three axes
};
std::string_view to_string(KdBuilder builder);
std::optional<KdBuilder> parse_kd_builder(std::string_view name);
const std::vector<std::string>& kd_builder_names();  ///< "median", "sah"

/// The deepest a KD tree may get (root = depth 0); traversal's stack has
/// kKdStackSize entries and pushes at most one per level.
inline constexpr int kKdMaxDepth = 62;
inline constexpr int kKdStackSize = 64;

/// Build and traversal parameters of the KD tree.
struct KdConfig {
    KdBuilder builder = KdBuilder::Sah;  ///< how planes are chosen
    int max_depth = 0;        ///< 0 = automatic, 8 + 1.3·log2(N) (Wald & Havran); else 1..kKdMaxDepth
    int leaf_size = 2;        ///< a node with at most this many references is a leaf (median: the only rule), >= 1
    /// SAH: C_trav, one interior-node step, >= 0. Twice C_isect: a node step (a
    /// dependent, cache-missing load) costs more than a test of a triangle stored
    /// contiguously in its leaf, and the tree is smaller (docs/performance.md).
    float cost_trav = 2.0f;
    float cost_isect = 1.0f;  ///< SAH: C_isect, one ray–triangle test, > 0
    float empty_bonus = 0.2f; ///< SAH: a plane that cuts off empty space costs (1 - bonus)·cost, in [0, 1)
    ClipMode clip = ClipMode::Exact;  ///< how a straddling triangle's box is cut to each side
    bool strict_cell = true;  ///< a hit counts only inside the current leaf (false: the lecture's naive, wrong rule)
    /// Skip triangles this ray already tested in an earlier leaf (the lecture's
    /// mailboxing). Off by default for the KD tree: its small leaves repeat few tests,
    /// and the per-test lookup costs more than it saves (docs/performance.md). The
    /// grid's crowded cells are another matter.
    bool mailbox = false;
    double max_duplication = 64.0;  ///< stop splitting once references exceed this · N (reported in notes), >= 1
    /// Triangles a leaf tests together, as the SAH counts them (kd_tests): 4 for
    /// Möller–Trumbore, whose walk tests a leaf's triangles four at a time; 1 for the
    /// watertight test, one at a time (build_accelerator sets it from the test).
    int leaf_lanes = 4;

    bool operator==(const KdConfig&) const = default;
};

/// A one-line error if a field is out of range (names the CLI flag).
std::optional<Error> validate(const KdConfig& config);

/// The max depth a config gives for N triangles.
int kd_max_depth(const KdConfig& config, size_t triangles);

/// One node, 8 bytes, as pbrt's KD tree node (Pharr, Jakob & Humphreys, "Physically
/// Based Rendering", 4.4): half the memory of a plain struct, and a cache line holds
/// four pairs of children.
/// A leaf holds prim_ids[first() .. first() + count()) (count may be 0: an empty leaf).
/// An interior node cuts its cell by the plane x_axis() = split(); its lower child
/// (x <= split) is nodes[lower_child()], its upper one the next node.
/// Packed: an interior node's plane is a float and a leaf's first index the same 32
/// bits; the other 32 bits hold the lower child's index or the leaf's count, shifted
/// past a 2-bit axis (3: a leaf).
struct KdNode {
    static constexpr bool kLeafLanes = true;  ///< leaves tested four triangles at a time (spatial_refs.h)
    static constexpr uint8_t kLeaf = 3;
    static constexpr uint32_t kMaxIndex = (1u << 30) - 1;  ///< the largest child index and leaf count
    /// The tree's node array starts 8 bytes into a cache line: the pairs of children,
    /// from nodes[1] on, then start on 16-byte boundaries and never straddle two lines.
    static constexpr size_t kLeadBytes = 8;

    static KdNode leaf(uint32_t first, uint32_t count) { return KdNode(first, count << 2 | kLeaf); }
    static KdNode interior(int axis, float split, uint32_t lower_child) {
        return KdNode(std::bit_cast<uint32_t>(split), lower_child << 2 | uint32_t(axis));
    }
    KdNode() = default;  // an empty leaf

    bool is_leaf() const { return (bits_ & 3u) == kLeaf; }
    bool is_empty_leaf() const { return bits_ == kLeaf; }
    int axis() const { return int(bits_ & 3u); }  ///< 0, 1, 2; kLeaf for a leaf
    float split() const { return std::bit_cast<float>(word_); }
    uint32_t lower_child() const { return bits_ >> 2; }
    uint32_t upper_child() const { return (bits_ >> 2) + 1; }
    uint32_t count() const { return is_leaf() ? bits_ >> 2 : 0; }
    /// A leaf's first index into prim_ids; an interior node's lower child.
    uint32_t first() const { return is_leaf() ? word_ : bits_ >> 2; }
    void set_first(uint32_t first) {
        if (is_leaf()) word_ = first;
        else bits_ = first << 2 | (bits_ & 3u);
    }

private:
    KdNode(uint32_t word, uint32_t bits) : word_(word), bits_(bits) {}
    uint32_t word_ = 0;     ///< the split (a float's bits) or the leaf's first index
    uint32_t bits_ = kLeaf; ///< lower child or count << 2 | axis (kLeaf)
};
static_assert(sizeof(KdNode) == 8, "a KD node is 8 bytes");

struct KdBuildStats : PartitionStats {
    uint32_t depth_limit = 0;  ///< the max depth the build used
    double sah_cost = 0;       ///< Σ interior P·C_trav + Σ leaf P·n·C_isect (P = area / root area; n in tests, kd_tests)
};

/// A KD tree over a mesh's triangles (invariants: PartitionTree's). A leaf holds
/// every triangle that comes within `padding` of its box (box or exact test, per
/// config.clip).
struct KdTree : PartitionTree<KdNode, KdConfig, KdBuildStats>, CellQueries<KdTree> {
    static constexpr AccelType kType = AccelType::Kd;
    std::string name() const { return std::string(to_string(kType)); }
    nlohmann::json config() const;
    nlohmann::json stats() const;

    /// The box of every node, by index. Nodes store only their split planes: the root's
    /// box is `bounds`, and a child's is its parent's cut at the parent's plane (the lower
    /// child keeps the part below it, the upper one the part above). What the stepper
    /// and the structure overlay draw.
    std::vector<Aabb> node_boxes() const;

private:
    friend struct CellQueries<KdTree>;
    /// The walk (CellQueries: intersect_closest, intersect_any), with the triangle test
    /// chosen at compile time. Events: BoxTest (root), VisitNode, SplitPlane, Push,
    /// Pop, Cull, Leaf (t_enter/t_exit = the leaf's t_min/t_max), TriangleTest,
    /// MailboxSkip, HitOutsideCell, NewClosest, Done.
    template <TriangleTestKind kTest, StopAt kStop, class Observer>
    Hit front_to_back(const Ray& ray, Observer& obs) const;
};

/// Builds the tree: an explicit work stack (no recursion), the top of the tree one
/// node at a time (a big node's sweeps and split spread over the threads), then the
/// subtrees below max(4096, N/64) references in parallel, each built on its own;
/// the output is the same on any number of threads.
/// build_stats.build_ms is wall time. `progress` (PartitionProgress's units) may
/// cancel the build: it then returns WorkProgress::cancelled_error().
Expected<KdTree> build_kd_tree(const Mesh& mesh, const KdConfig& config, WorkProgress* progress = nullptr);

// ---------------------------------------------------------------------------
// Front-to-back traversal.
// ---------------------------------------------------------------------------

template <TriangleTestKind kTest, StopAt kStop, class Observer>
Hit KdTree::front_to_back(const Ray& ray, Observer& obs) const {
    using Hits = CellHits<kTest, kStop>;
    const RayPrecomp pre(ray);
    CellWalk<kKdStackSize> walk;
    CellWalk<kKdStackSize>::Entry cur;
    if (nodes.empty() || !walk.start(bounds, pre, ray, cur, obs)) return Hits::missed(obs);
    Hits hits(ray, pre, triangles, corners, build_config.mailbox, build_config.strict_cell, build_stats.triangles);
    // Plain arrays: indexed by a node's axis, Vec3's operator[] would be a chain of selects.
    const float origin[3] = {ray.origin.x, ray.origin.y, ray.origin.z};
    const float dir_inv[3] = {pre.dir_inv.x, pre.dir_inv.y, pre.dir_inv.z};
    const bool dir_negative[3] = {pre.dir_negative[0] != 0, pre.dir_negative[1] != 0, pre.dir_negative[2] != 0};
    do {
        // Down to the leaf holding the start of [t_min, t_max], deferring far children.
        walk.visit(cur, obs);
        const KdNode* n = &nodes[cur.node];
        while (!n->is_leaf()) {
            const int a = n->axis();
            const float t_split = (n->split() - origin[a]) * dir_inv[a];
            // Moving up the axis (or along it, +0) the lower child comes first.
            const bool lower_first = !dir_negative[a];
            const uint32_t lower = n->lower_child();
            const uint32_t near = lower + (lower_first ? 0 : 1), far = lower + (lower_first ? 1 : 0);
            obs.on({.kind = EventKind::SplitPlane, .axis = uint8_t(a), .near_first = lower_first, .node = cur.node,
                    .t = t_split, .split = n->split()});
            // (The SAH's empty-space cuts make many empty leaves: cross_plane skips them.)
            walk.cross_plane(cur, t_split, near, far, nodes.data(), obs);
            walk.visit(cur, obs);
            n = &nodes[cur.node];
        }
        // A leaf: its triangles, with the in-cell rule; then the next deferred subtree.
        if constexpr (kTest == TriangleTestKind::MollerTrumbore) {
            if (walk.template test_leaf_lanes<FastLanes<4>>(cur, n->first(), n->count(), prim_ids.data(), leaf_lanes,
                                                            hits, obs))
                break;
        } else if (walk.template test_leaf<kOneCopyPerTriangle>(cur, n->first(), n->count(), prim_ids.data(),
                                                                copy_index.data(), hits, obs)) {
            break;
        }
    } while (walk.pop_next(hits, cur, obs));
    return hits.done(obs);
}

}  // namespace accelviz
