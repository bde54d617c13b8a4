#pragma once
/// Building a BVH (lecture: 层次包围盒的构建): a free function of (mesh, config)
/// returning plain data and its stats. Four builders choose the splits:
/// midpoint and median (the lecture's heuristics), full-sweep SAH and binned SAH.
///
/// The build is top-down. Subtrees of a few thousand triangles are built depth first
/// over an explicit work stack; above that the two children of a node are built in
/// parallel (oneTBB), a recursion no deeper than the depth budget (kBvhMaxDepth). The
/// tree does not depend on the number of threads: same nodes, same order, bit for bit.
/// Each node gets exactly one BuildDecision; an
/// optional BuildRecorder receives every decision as data (node, axis, candidate
/// costs, chosen split, leaf cost) so the construction can be stepped split by split.

#include <array>
#include <vector>

#include "core/accel/bvh.h"
#include "core/geometry/mesh.h"
#include "core/util/work_progress.h"

namespace accelviz {

/// One decision of the builder, for the construction stepper. Node ranges are
/// final: the triangles of node `node` are bvh.prim_ids[first .. first+count).
struct BuildStep {
    uint32_t node = 0;
    uint32_t depth = 0;
    uint32_t first = 0, count = 0;
    Aabb bounds;              ///< the node's box (union of its triangles' boxes)
    Aabb centroid_bounds;     ///< box of its triangles' centroids (what the splits divide)
    BuildDecision decision = BuildDecision::LeafFits;
    int axis = -1;            ///< split axis (0 x, 1 y, 2 z); -1 for a leaf or a split by index
    float split_position = 0; ///< where the plane cuts the axis (centroid coordinate); 0 if axis == -1
    uint32_t left_count = 0;  ///< triangles that went to the left child (0 for a leaf)
    float leaf_cost = 0;      ///< N · C_isect
    /// SAH cost of the split actually made (children's real boxes), +inf for a leaf.
    float split_cost = kInfinity;
    /// SAH builders: every candidate plane per axis, in increasing position, with its
    /// cost (+inf where one side would be empty or no plane fits between equal centroids).
    /// sah-binned: bins - 1 planes per axis; sah-sweep: count - 1 per axis. Empty for
    /// midpoint and median, and for an axis whose centroid extent is zero.
    std::array<std::vector<float>, 3> candidate_positions;
    std::array<std::vector<float>, 3> candidate_costs;
};

/// Receives the build's decisions in the order they are made (parents before
/// children, depth first, left before right).
struct BuildRecorder {
    std::vector<BuildStep> steps;
    /// false: the steps' candidate lists stay empty (a big mesh's candidates take
    /// hundreds of bytes per node; the stepper recomputes one node's with sah_chart.h).
    bool record_candidates = true;
};

/// Builds a BVH over `mesh`; a config that validate() refuses is an error (its
/// message). With a recorder, every node's decision is appended to recorder->steps (the
/// build then runs on one thread, so the steps come in depth-first order). `progress`
/// counts triangles placed in leaves; cancelling it makes the build stop and return
/// WorkProgress::cancelled_error().
Expected<Bvh> build_bvh(const Mesh& mesh, const BvhConfig& config, BuildRecorder* recorder = nullptr,
                        WorkProgress* progress = nullptr);

/// Refit, a moving scene's cheap update: `bvh` was built over `mesh` before its
/// vertices moved (the same triangles, the same ids). Keeps the tree (its splits and
/// leaves) and recomputes every box bottom up, a leaf's from its triangles' boxes and
/// an interior node's from its children's, then re-reads the leaf-order triangles.
/// One pass over the nodes, no sorting, but the splits were chosen for the old
/// positions: as triangles move, boxes stretch and overlap and the tree's SAH cost
/// grows, while a rebuild keeps it low. Refitting to the mesh the tree was built over
/// gives the built boxes exactly. Another triangle count is an error.
/// build_stats.refit_ms says how long it took; the other statistics are the build's
/// until gather_refit_stats() (a renderer refitting every frame would not need them).
std::optional<Error> refit_bvh(Bvh& bvh, const Mesh& mesh);

/// The statistics of a refitted tree (SAH cost, depths, leaf sizes, over its new
/// boxes), and a note that its decisions, other notes and build_ms are the build's.
void gather_refit_stats(Bvh& bvh);

}  // namespace accelviz
