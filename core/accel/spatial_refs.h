#pragma once
/// Triangle references of the space-partitioning trees (KD tree, octree) while
/// they are built: which part of a triangle lies in a node, and how a reference
/// follows a split. A triangle that straddles a split plane goes to both sides
/// (lecture: 同一个基元可以包含在空间的多个区域中), with its box clipped to each side.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/geometry/mesh.h"
#include "core/geometry/triangle.h"

namespace accelviz {

/// How a straddling triangle's box is cut down to a child.
enum class ClipMode : uint8_t {
    Box,    ///< box ∩ child box: cheap, keeps corners the triangle never reaches
    Exact,  ///< the triangle polygon clipped to the child, then its bounds ("perfect splits", Wald & Havran 2006)
};
std::string_view to_string(ClipMode mode);
std::optional<ClipMode> parse_clip_mode(std::string_view name);
const std::vector<std::string>& clip_mode_names();  ///< "box", "exact"

/// A triangle in a node under construction.
/// Invariant: `box` is the bounds of (triangle ∩ (node box grown by pad)),
/// grown by pad again. So, for a split plane s on axis a, the triangle comes
/// within pad of the lower child iff box.lo[a] < s, of the upper iff box.hi[a] > s
/// (both: it straddles). See reference_padding() for why the margin exists.
struct SpatialRef {
    uint32_t tri;
    Aabb box;
};

/// The references of a whole mesh in its root box `root` (the scene box grown by pad).
std::vector<SpatialRef> root_references(const Mesh& mesh, float pad);

/// `ref` restricted to `child` (a box inside the node `ref` belongs to), or
/// nothing if the triangle does not come within pad of `child` (possible with
/// Exact: the box reaches the child, the triangle does not).
std::optional<SpatialRef> clip_reference(const SpatialRef& ref, const Mesh& mesh, const Aabb& child, float pad,
                                         ClipMode mode);

/// The arrays of a space-partitioning tree (KD tree, octree) and what it was built
/// with. Invariants of both: nodes[0] is the root and `bounds` its box (the scene's
/// box grown by the reference padding); nodes is empty iff the mesh has no
/// triangles; triangles[k] is triangle prim_ids[k] (leaf order: a copy, so that a
/// leaf's triangles are contiguous in memory).
template <class Node, class Config, class Stats>
struct PartitionTree {
    Aabb bounds;
    std::vector<Node> nodes;
    std::vector<uint32_t> prim_ids;
    std::vector<Triangle> triangles;
    Config build_config;
    Stats build_stats;

    /// The statistics the arrays determine, at the end of a build that began at `start`.
    void finish_stats(std::chrono::steady_clock::time_point start) {
        Stats& st = build_stats;
        st.nodes = uint32_t(nodes.size());
        st.references = prim_ids.size();
        st.duplication = st.triangles ? double(st.references) / st.triangles : 0.0;
        st.memory_bytes = nodes.size() * sizeof(Node) + prim_ids.size() * sizeof(uint32_t) +
                          triangles.size() * sizeof(Triangle);
        st.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    }
};

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

/// The mesh's triangles in leaf order: out[k] is triangle prim_ids[k] (a copy, so a
/// leaf's triangles are contiguous in memory).
std::vector<Triangle> triangles_in_leaf_order(const Mesh& mesh, const std::vector<uint32_t>& prim_ids);

}  // namespace accelviz
