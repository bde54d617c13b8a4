#pragma once
/// Triangle references of the space-partitioning trees (KD tree, octree) while
/// they are built: which part of a triangle lies in a node, and how a reference
/// follows a split. A triangle that straddles a split plane goes to both sides
/// (lecture: 同一个基元可以包含在空间的多个区域中), with its box clipped to each side.

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/geometry/mesh.h"
#include "core/geometry/triangle.h"
#include "core/geometry/triangle_box.h"
#include "core/geometry/triangle_lanes.h"
#include "core/util/large_array.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// Which children a straddling triangle goes to, and its box there (the user's choice;
/// PartRule is how the KD tree carries it out, OctantSplit how the octree does).
enum class ClipMode : uint8_t {
    Box,    ///< every child its box reaches, with box ∩ child: cheap, keeps corners the triangle never reaches
    Exact,  ///< only the children the triangle reaches; the KD tree also gets each part's bounds ("perfect splits", Wald & Havran 2006)
};
std::string_view to_string(ClipMode mode);
std::optional<ClipMode> parse_clip_mode(std::string_view name);
const std::vector<std::string>& clip_mode_names();  ///< "box", "exact"

/// A triangle in a node under construction.
/// Invariant: `box` contains the bounds of (triangle ∩ (node box grown by pad)),
/// grown by pad again, and lies within the node box grown by 2·pad (PartRule says how
/// tight it is). So, for a split plane s on axis a, the triangle can come within pad
/// of the lower child only if box.lo[a] < s, of the upper only if box.hi[a] > s (both:
/// it straddles). With the tight box (PartRule::Clipped) these are "if and only if".
/// See reference_padding() for why the margin exists.
struct SpatialRef {
    uint32_t tri;
    Aabb box;
};

/// A node's references. At the top of a tree at ten million triangles a list holds
/// hundreds of megabytes: on huge pages (large_array.h) it takes a few hundred page
/// faults instead of tens of thousands.
using SpatialRefs = std::vector<SpatialRef, LargeArrayAllocator<SpatialRef>>;

/// Each triangle's three corners side by side (36 bytes a triangle): what
/// split_reference and OctantSplit read of a straddling triangle, one load where the mesh takes an
/// index triple and then three scattered positions (docs/performance.md: waiting for
/// the index triple was a tenth of the octree's build). triples[k] is triangle
/// order[k], or triangle k when `order` is empty.
using CornerTriples = std::vector<std::array<Vec3, 3>, LargeArrayAllocator<std::array<Vec3, 3>>>;
CornerTriples corner_triples(const Mesh& mesh, std::span<const uint32_t> order = {});

/// The references of a whole mesh in its root box `root` (the scene box grown by pad).
SpatialRefs root_references(const Mesh& mesh, float pad);

/// How split_reference finds the children a reference straddling a split goes to, and
/// its box in each.
enum class PartRule : uint8_t {
    BoxOverlap,  ///< ClipMode::Box: each child the box reaches; there, box ∩ (child grown by 2·pad)
    Clipped,     ///< ClipMode::Exact: the triangle clipped to each child; there, the part's bounds
};
/// The rule for `mode` (the KD tree's; the octree has OctantSplit).
PartRule part_rule(ClipMode mode);

/// What split_reference gives: the reference's part in each child it reaches, in
/// increasing child index.
struct ChildRefs {
    int count = 0;
    uint8_t child[8];
    SpatialRef ref[8];
};

/// `ref`, a reference of the node `cell`, split among the node's children: the cell cut
/// at planes[a] on each axis a in `axes` (a bit per axis: the KD tree cuts one; the
/// tests also cut three, as a check of the polygon cut over several planes). Child o
/// lies above planes[a] iff bit a of o is set. A reference reaches the children its box
/// reaches (below iff lo < plane or not hi > plane, above iff hi > plane: see
/// SpatialRef), and in each its box is cut down to that child per `rule`; with Clipped,
/// a child the triangle does not come within pad of gets nothing (the box reaches it,
/// the triangle does not), and the triangle is clipped to the cell once and that
/// polygon cut at the planes for each child. The KD tree's SAH places its planes at the
/// boxes' sides, so it needs each part's tight box.
void split_reference(const SpatialRef& ref, const CornerTriples& triangles, const Aabb& cell, Vec3 planes, unsigned axes,
                     float pad, PartRule rule, ChildRefs& out);

/// The octree's split of a cell at its centre into eight octants (child o above the
/// centre on axis a iff bit a of o is set). The octree's planes are fixed, so it needs
/// only which octants a triangle is in, not each part's box: a reference's box there is
/// box ∩ (octant grown by 2·pad), the same floats split_reference's BoxOverlap gives.
/// Each octant's bounds grown by pad and by 2·pad are worked out once per cell, per
/// axis and side, and a reference's octants come out as a bit mask.
class OctantSplit {
public:
    OctantSplit(const Aabb& cell, float pad, ClipMode mode);

    /// Where the cell is cut: its box's centre (Aabb::center), the octree node's centre.
    Vec3 centre() const { return {centre_.v[0], centre_.v[1], centre_.v[2]}; }
    /// The cell grown by 2·pad: what a reference's box in it lies within (SpatialRef).
    const Aabb& limit() const { return limit_; }

    /// The octants (bit o for octant o) that the reference with box `box` (a reference of
    /// this cell: see SpatialRef) and triangle `corners` reaches. ClipMode::Box: every
    /// octant the box reaches. Exact, of those, the octants the triangle comes within pad
    /// of: an octant that holds the whole box (grown by 2·pad) or one of the corners
    /// (grown by pad) without a test (a straddler inside the cell reaches both sides with
    /// a corner), the others by the separating axis test (TriangleAxes, worked out once
    /// for the triangle). The same octants as split_reference's Clipped up to rounding
    /// well inside pad.
    uint32_t reached(const Aabb& box, const std::array<Vec3, 3>& corners) const;

    /// x, y, z and a fourth float that no test reads: what the tests compare, axis by
    /// axis, three at a time (one SSE comparison where the build has SSE).
    struct alignas(16) Xyz {
        float v[4];
    };

private:
    bool exact_;
    Aabb limit_;
    Xyz centre_;
    // Per side (0 below the centre, 1 above) and axis: the octant's bounds grown by
    // 2·pad and by pad.
    Xyz limit_lo_[2], limit_hi_[2], reach_lo_[2], reach_hi_[2];
};

/// A space-partitioning build's progress, counted so that it adds up whatever the
/// references' duplication: the root holds kTotal units, a split hands a node's
/// units to its children in proportion to their references, and a leaf's units are
/// done. One per thread of the build: leaves are tallied here and reach the shared
/// WorkProgress in steps of 1/1024 of the total (an atomic add per step, not per leaf).
class PartitionProgress {
public:
    static constexpr uint64_t kTotal = uint64_t(1) << 40;
    explicit PartitionProgress(WorkProgress* shared) : shared_(shared) {}
    ~PartitionProgress() { flush(); }
    PartitionProgress(const PartitionProgress&) = delete;
    PartitionProgress& operator=(const PartitionProgress&) = delete;

    bool cancelled() const { return accelviz::cancelled(shared_); }
    void leaf_done(uint64_t units) {
        tally_ += units;
        if (tally_ >= kTotal / 1024) flush();
    }
    void flush() {
        advance(shared_, tally_);
        tally_ = 0;
    }
    /// Counts 1/`parts` of a node's `units` now and returns the rest, for its children
    /// or its subtree to count as their leaves are made. For the work a node does before
    /// any leaf exists below it: the top of a tree is cut one node at a time, which at
    /// ten million triangles takes seconds, and the bar should move meanwhile.
    uint64_t count_part(uint64_t units, uint64_t parts) {
        const uint64_t now = units / parts;
        leaf_done(now);
        return units - now;
    }
    /// The units of a child holding `child_refs` of the `all_refs` references its
    /// parent's children hold (give the last child what the others leave).
    static uint64_t share_of(uint64_t units, size_t child_refs, size_t all_refs) {
        return all_refs == 0 ? 0 : uint64_t(double(units) * (double(child_refs) / double(all_refs)));
    }

private:
    WorkProgress* shared_;
    uint64_t tally_ = 0;
};

/// Nodes with this many references or more share their own work out over the threads
/// (split_in_order; the KD tree also sweeps its three axes at once). Such nodes make up
/// the top of a tree, which is built one node at a time (below it, whole subtrees run
/// in parallel). A fixed size, so the same on any number of threads.
inline constexpr size_t kRefsToShareOut = 8192;

/// part(k) for k in [0, parts), the independent parts of one node's work (an axis, a
/// list): as tasks over the threads for a node of kRefsToShareOut references or more,
/// one after another for a smaller one.
template <class Part>
void for_each_part(size_t node_refs, int parts, Part&& part) {
    if (node_refs < kRefsToShareOut) {
        for (int k = 0; k < parts; ++k) part(k);
    } else {
        tbb::parallel_for(0, parts, part);
    }
}

/// When the top of a KD tree or octree hands a node on to be built as a subtree, 1/4
/// of the node's progress units count at once (PartitionProgress::count_part): about
/// the top's share of the build's work (docs/performance.md).
inline constexpr uint64_t kTopParts = 4;

/// A node's `n` references split among K children: split_range(begin, end, lists)
/// appends references [begin, end) to the children's lists. For kRefsToShareOut
/// references or more, chunks of that size are split in parallel into lists of their
/// own, then appended to `children` chunk after chunk: the lists one pass would give.
/// A chunk starts only while the build is wanted: once `progress` is cancelled the
/// lists are left short, and the caller, which checks right after, drops them with the tree.
template <class Refs, size_t K, class SplitRange>
void split_in_order(size_t n, std::array<Refs, K>& children, const PartitionProgress& progress,
                    SplitRange&& split_range) {
    if (n < kRefsToShareOut) {
        split_range(size_t(0), n, children);
        return;
    }
    std::vector<std::array<Refs, K>> chunks((n + kRefsToShareOut - 1) / kRefsToShareOut);
    tbb::parallel_for(size_t(0), chunks.size(), [&](size_t k) {
        if (progress.cancelled()) return;
        split_range(k * kRefsToShareOut, std::min(n, (k + 1) * kRefsToShareOut), chunks[k]);
    });
    for (size_t c = 0; c < K; ++c) {
        size_t count = children[c].size();
        for (const auto& chunk : chunks) count += chunk[c].size();
        children[c].reserve(count);
        for (const auto& chunk : chunks) children[c].insert(children[c].end(), chunk[c].begin(), chunk[c].end());
    }
}

/// What the builds of the space-partitioning trees report (KD tree, octree, BSP tree).
struct PartitionStats {
    uint32_t triangles = 0;
    uint32_t nodes = 0;
    uint32_t leaves = 0;
    uint32_t empty_leaves = 0;
    uint32_t max_depth = 0;              ///< deepest leaf (root = 0)
    uint32_t leaves_at_depth_limit = 0;  ///< leaves over leaf_size because of the depth limit
    uint64_t references = 0;             ///< Σ leaf sizes
    double duplication = 0;              ///< references / triangles
    uint32_t max_leaf_size = 0;
    float padding = 0;                   ///< the references' safety margin (reference_padding)
    uint64_t memory_bytes = 0;           ///< nodes + prim_ids + the triangle copy (+ copy_index, copy_order)
    double build_ms = 0;
    std::vector<std::string> notes;
};
/// Its fields as JSON (bench, trace and the Stats panel), keyed by field name.
nlohmann::json partition_stats_json(const PartitionStats& stats);

/// What stopped a space-partitioning build from splitting further (KD tree,
/// octree), for the notes that bench and the Stats panel show.
struct SplitStops {
    const char* parts = "nodes";       ///< what the tree splits: "nodes" (KD tree), "cells" (octree)
    uint32_t leaves_at_depth_limit = 0;
    int depth_limit = 0;
    int leaf_size = 0;
    uint32_t not_split = 0;             ///< parts made leaves because no split separates their triangles
    std::string not_split_why;          ///< the builder's reason, e.g. "no axis' middle plane separates their triangles"
    bool budget_hit = false;            ///< the reference budget (max_duplication · N) was reached
    double max_duplication = 0;
};
/// One note per stop that happened, in plain words with the numbers.
void add_split_notes(const SplitStops& stops, std::vector<std::string>& notes);

/// What a subtree of a space-partitioning tree (KD tree, octree), built on its own
/// by a parallel build, adds to its tree's statistics.
struct SubtreeCounts {
    uint32_t leaves = 0, empty_leaves = 0, max_depth = 0, leaves_at_depth_limit = 0, max_leaf_size = 0;
    uint32_t no_progress = 0;  ///< parts made leaves because no split made progress
    bool budget_hit = false;   ///< a split refused for the reference budget

    /// A leaf of `n` references at `depth`: over `leaf_size` at `depth_limit`, it
    /// stopped because of the limit.
    void add_leaf(size_t n, uint32_t depth, int depth_limit, int leaf_size) {
        ++leaves;
        if (n == 0) ++empty_leaves;
        if (depth >= uint32_t(depth_limit) && n > size_t(leaf_size)) ++leaves_at_depth_limit;
        max_depth = std::max(max_depth, depth);
        max_leaf_size = std::max(max_leaf_size, uint32_t(n));
    }
    /// Adds another subtree's counts (the tree's are the sum over its subtrees).
    void add(const SubtreeCounts& o) {
        leaves += o.leaves;
        empty_leaves += o.empty_leaves;
        max_depth = std::max(max_depth, o.max_depth);
        leaves_at_depth_limit += o.leaves_at_depth_limit;
        max_leaf_size = std::max(max_leaf_size, o.max_leaf_size);
        no_progress += o.no_progress;
        budget_hit = budget_hit || o.budget_hit;
    }
    /// Writes the leaf counts into the tree's stats.
    void write_to(PartitionStats& st) const {
        st.leaves = leaves;
        st.empty_leaves = empty_leaves;
        st.max_depth = max_depth;
        st.leaves_at_depth_limit = leaves_at_depth_limit;
        st.max_leaf_size = max_leaf_size;
    }
};

/// Where a tree's node array starts after a cache line's start: Node::kLeadBytes if the
/// node type says (the KD tree's, so that its pairs of children never straddle two
/// lines), else 0.
template <class Node>
constexpr size_t node_lead_bytes() {
    if constexpr (requires { Node::kLeadBytes; }) return Node::kLeadBytes;
    else return 0;
}

/// Whether a tree keeps one copy of each triangle (Node::kOneCopyPerTriangle: the
/// octree's) rather than one per reference in leaf order.
template <class Node>
constexpr bool one_copy_per_triangle() {
    if constexpr (requires { Node::kOneCopyPerTriangle; }) return Node::kOneCopyPerTriangle;
    else return false;
}

/// Whether a tree of these nodes keeps its leaves' triangles as lanes
/// (LeafTriangleLanes, geometry/triangle_lanes.h: Möller–Trumbore four at a time)
/// instead of one Triangle each (a node type says so with kLeafLanes = true).
template <class Node>
constexpr bool keeps_leaf_lanes() {
    if constexpr (requires { Node::kLeafLanes; }) return Node::kLeafLanes;
    else return false;
}

/// The arrays of a space-partitioning tree (KD tree, octree, BSP tree) and what it was built
/// with. The nodes and ids are on huge pages, as the BVH's (large_array.h): a ray's
/// walk reads a few nodes scattered over the whole array. Invariants of all three: nodes[0]
/// is the root and `bounds` its box (the scene's box grown by the reference padding);
/// nodes is empty iff the mesh has no triangles; triangles[k] is triangle prim_ids[k]
/// (leaf order: a copy per reference, so that a leaf's triangles are contiguous in
/// memory; with kLeafLanes, the KD tree's, the same copy is kept as leaf_lanes and
/// `triangles` is empty), or with kOneCopyPerTriangle triangles[copy_index[k]] is triangle
/// prim_ids[k] (one copy of each triangle, in the build's order copy_order: a tree that
/// holds each triangle many times, as the octree does, keeps one copy instead of one
/// per reference).
template <class Node, class Config, class Stats>
struct PartitionTree {
    static constexpr bool kOneCopyPerTriangle = one_copy_per_triangle<Node>();
    static constexpr bool kLeafLanes = keeps_leaf_lanes<Node>();
    static_assert(!(kOneCopyPerTriangle && kLeafLanes), "leaf lanes are a copy per reference");

    Aabb bounds;
    std::vector<Node, LargeArrayAllocator<Node, node_lead_bytes<Node>()>> nodes;
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> prim_ids;
    std::vector<uint32_t, LargeArrayAllocator<uint32_t>> copy_index;  ///< kOneCopyPerTriangle: where prim_ids[k] is in triangles
    std::vector<uint32_t> copy_order;                              ///< kOneCopyPerTriangle: triangles[j] is triangle copy_order[j]
    TriangleArray triangles;  ///< empty with kLeafLanes: the leaves' triangles are in leaf_lanes
    LeafTriangleLanes leaf_lanes;  ///< kLeafLanes: each leaf's triangles as lanes, in leaf order
    CornerArray corners;  ///< leaf order (or copy_order), as corners; only when triangle_test is watertight
    Config build_config;
    Stats build_stats;
    TriangleTestKind triangle_test = TriangleTestKind::MollerTrumbore;  ///< which ray-triangle test the leaves run

    /// A build's first step: the config and the triangle count recorded, and the root's
    /// box (the scene's box grown by the references' padding, reference_padding).
    /// Returns the padding; 0 for a mesh without triangles, whose tree is then
    /// finished (empty, with a note).
    float begin_build(const Mesh& mesh, const Config& config, std::chrono::steady_clock::time_point start) {
        build_config = config;
        build_stats.triangles = uint32_t(mesh.triangle_count());
        if (build_stats.triangles == 0) {
            build_stats.notes.push_back("empty scene: no nodes");
            finish_stats(start);
            return 0.0f;
        }
        const Aabb scene = mesh.bounds();
        build_stats.padding = reference_padding(scene);
        bounds = padded(scene, build_stats.padding);
        return build_stats.padding;
    }

    /// A build's last step, once nodes and prim_ids are final (prim_ids naming the
    /// triangles by their place in `order` if it is given: they become the mesh's ids
    /// first): the triangles copied, into leaf order or by id (a stage of `progress` of
    /// its own: seconds at ten million triangles), a note for each thing that stopped
    /// the splitting, the stats.
    void end_build(const Mesh& mesh, const SplitStops& stops, std::chrono::steady_clock::time_point start,
                   WorkProgress* progress, std::vector<uint32_t> order = {}) {
        if constexpr (kOneCopyPerTriangle) {
            // prim_ids are the triangles' places in `order` still: where their one copy goes.
            copy_index.assign(prim_ids.begin(), prim_ids.end());
            copy_order = std::move(order);
            if (!copy_order.empty()) to_mesh_ids(copy_order);
            start_stage(progress, mesh.triangle_count(), "copying the triangles");
            triangles = make_triangles(mesh, copy_order, progress);
        } else {
            if (!order.empty()) to_mesh_ids(order);
            start_stage(progress, prim_ids.size(), "putting the triangles in leaf order");
            triangles = make_triangles(mesh, prim_ids, progress);
            if constexpr (kLeafLanes) make_leaf_lanes();
        }
        add_split_notes(stops, build_stats.notes);
        finish_stats(start);
    }

    /// kLeafLanes: `triangles` (leaf order) moved into `leaf_lanes`, leaf by leaf.
    void make_leaf_lanes() {
        leaf_lanes.resize(triangles.size());
        tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
            for (size_t n = r.begin(); n < r.end(); ++n) {
                const Node& node = nodes[n];
                if (!node.is_leaf()) continue;
                for (uint32_t j = 0; j < node.count(); ++j)
                    leaf_lanes.set(node.first(), node.count(), j, triangles[node.first() + j]);
            }
        });
        triangles = {};
    }

    /// The order of `triangles`, as make_triangles and make_corners take it: leaf order
    /// (prim_ids) or copy_order.
    std::span<const uint32_t> triangle_order() const {
        if constexpr (kOneCopyPerTriangle) return copy_order;
        else return prim_ids;
    }

    /// Appends the subtrees built on their own (each with `nodes`, its root at nodes[0],
    /// child indices local to it, and `prim_ids`, leaf ranges local to them), subtree k's
    /// root replacing the placeholder node at[k], in that order: how the builds splice
    /// in the subtrees built in parallel.
    template <class Subtree>
    void splice_all(const std::vector<uint32_t>& at, const std::vector<Subtree>& subtrees) {
        size_t node_count = nodes.size(), id_count = prim_ids.size();
        for (const Subtree& sub : subtrees) {
            node_count += sub.nodes.empty() ? 0 : sub.nodes.size() - 1;  // each root takes its placeholder's place
            id_count += sub.prim_ids.size();
        }
        nodes.reserve(node_count);
        prim_ids.reserve(id_count);
        for (size_t k = 0; k < subtrees.size(); ++k) splice(at[k], subtrees[k].nodes, subtrees[k].prim_ids);
    }

private:
    /// prim_ids[k] = order[prim_ids[k]], in parallel.
    void to_mesh_ids(std::span<const uint32_t> order) {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, prim_ids.size(), size_t(1) << 16),
                          [&](const tbb::blocked_range<size_t>& r) {
                              for (size_t k = r.begin(); k < r.end(); ++k) prim_ids[k] = order[prim_ids[k]];
                          });
    }

    // A node's first child or first reference: a field of the octree's and BSP tree's
    // nodes, packed into the KD tree's (methods).
    static uint32_t first_of(const Node& n) {
        if constexpr (requires { n.first(); }) return n.first();
        else return n.first;
    }
    static void set_first(Node& n, uint32_t first) {
        if constexpr (requires { n.set_first(first); }) n.set_first(first);
        else n.first = first;
    }

    void splice(uint32_t at, const std::vector<Node>& sub_nodes, const std::vector<uint32_t>& sub_prim_ids) {
        const auto base = uint32_t(nodes.size());  // where the subtree's node 1 goes
        const auto prim_base = uint32_t(prim_ids.size());
        for (size_t i = 0; i < sub_nodes.size(); ++i) {
            Node n = sub_nodes[i];
            const uint32_t first = first_of(n);
            set_first(n, n.is_leaf() ? first + prim_base : (first == 0 ? at : base + first - 1));
            if (i == 0) nodes[at] = n;
            else nodes.push_back(n);
        }
        prim_ids.insert(prim_ids.end(), sub_prim_ids.begin(), sub_prim_ids.end());
    }

    /// The statistics the arrays determine, at the end of a build that began at `start`.
    void finish_stats(std::chrono::steady_clock::time_point start) {
        Stats& st = build_stats;
        st.nodes = uint32_t(nodes.size());
        st.references = prim_ids.size();
        st.duplication = st.triangles ? double(st.references) / st.triangles : 0.0;
        st.memory_bytes = nodes.size() * sizeof(Node) + (prim_ids.size() + copy_index.size()) * sizeof(uint32_t) +
                          copy_order.size() * sizeof(uint32_t) + triangles.size() * sizeof(Triangle) +
                          leaf_lanes.memory_bytes();
        st.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
};

}  // namespace accelviz
