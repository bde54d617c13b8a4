#pragma once
/// The SAH chart of one BVH node, for the construction stepper (lecture: 如何衡量划分的质量？):
/// for each axis the cost of every candidate plane, the leaf cost, the cheapest
/// split, and where the lecture's two heuristics (midpoint, median) would cut,
/// with their SAH costs. Plain data, recomputed from the node's triangles alone,
/// so sliders for B, C_trav and C_isect can redraw one node's chart without
/// rebuilding the tree. The numbers are the builder's own: the same bins, the same
/// prefix/suffix boxes and the same SahCostModel (tests compare them with a
/// BuildRecorder's, candidate by candidate).

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/accel/bvh_build.h"
#include "core/accel/sah.h"
#include "core/geometry/mesh.h"

namespace accelviz {

/// The candidate planes of one axis.
struct SahChartAxis {
    bool usable = false;            ///< the centroids spread along this axis (else no plane separates them)
    float lo = 0, hi = 0;           ///< the centroid bounds on this axis: the chart's x range
    /// Candidate planes in increasing position (centroid coordinates), with their SAH
    /// cost (+inf where one side would be empty, or the plane falls between equal
    /// centroids) and how many triangles would go left.
    std::vector<float> positions;
    std::vector<float> costs;
    std::vector<uint32_t> left_counts;
    size_t candidates = 0;          ///< how many planes the builder evaluates on this axis
    /// True when only some candidates are listed (sweep on a large node): each listed
    /// one is the best of a run of `stride` neighbours (is_better_split), so the minimum is kept.
    bool subsampled = false;
    size_t stride = 1;
};

/// Where a heuristic would cut this node, and what that cut costs by the SAH.
struct HeuristicCut {
    bool valid = false;        ///< false: all centroids equal (no plane)
    int axis = -1;             ///< the longest axis of the centroid bounds
    float position = 0;        ///< the plane, as a centroid coordinate
    uint32_t left_count = 0;
    float cost = kInfinity;    ///< SAH cost with the children's real boxes
    /// midpoint only: the middle plane leaves one side empty; the builder then
    /// cuts at the median (position, left_count and cost are the median's).
    bool median_fallback = false;
};

/// What the builder would do with this node under the chart's parameters.
enum class ChartVerdict : uint8_t {
    LeafOneTriangle,     ///< a single triangle is always a leaf
    LeafFits,            ///< midpoint/median: the node fits in a leaf
    LeafCheaper,         ///< SAH: no split is cheaper than the leaf, and the leaf fits
    LeafNoPlane,         ///< SAH: all centroids equal, no plane separates them, and the leaf fits
    Split,               ///< SAH: the cheapest split beats the leaf; heuristics: their cut
    SplitForcedBySize,   ///< SAH: the leaf is cheaper but too big: the cheapest split anyway
    SplitInHalf,         ///< all centroids equal and the leaf is too big: split by index
};

struct SahChart {
    BvhBuilder builder = BvhBuilder::SahBinned;
    /// Candidates: "binned" (B - 1 bucket boundaries per axis) or "sweep" (every
    /// centroid). Midpoint and median builds are charted with binned candidates.
    bool sweep = false;
    int bins = 16;
    SahCostModel model;
    int max_leaf_size = 4;

    uint32_t count = 0;
    Aabb bounds;           ///< the node's box
    Aabb centroid_bounds;  ///< the box of its triangles' centroids
    std::array<SahChartAxis, 3> axes;
    float leaf_cost = 0;   ///< N · C_isect

    /// The cheapest candidate over all axes, by the builder's rule (is_better_split in
    /// sah.h: of equal costs the most even, then the first). best_axis = -1 when no
    /// candidate has a finite cost.
    int best_axis = -1;
    float best_position = 0;
    float best_cost = kInfinity;
    uint32_t best_left_count = 0;
    /// Another candidate costs exactly best_cost but divides the triangles differently
    /// (e.g. "all boxes equal": every plane ties), so evenness decided.
    bool best_tied = false;
    Aabb best_children[2];  ///< the boxes the cheapest split would make ([0] left)

    HeuristicCut midpoint, median;
    ChartVerdict verdict = ChartVerdict::LeafOneTriangle;
    std::string verdict_text;  ///< one sentence, with the numbers: why a leaf or a split
};

struct SahChartOptions {
    /// Sweep on a node with more triangles than this: list at most this many candidates
    /// per axis (each the best of its run, by is_better_split). 0: list every candidate.
    size_t max_points = 0;
};

/// The chart of the node whose triangles are `prim_ids` (ids into `mesh`) under
/// `config` (builder, bins, cost_trav, cost_isect, max_leaf_size). Costs equal the
/// builder's for the same parameters. A config validate() refuses gives an empty
/// chart whose verdict_text says why.
SahChart compute_sah_chart(const Mesh& mesh, std::span<const uint32_t> prim_ids, const BvhConfig& config,
                           const SahChartOptions& options = {});

/// One sentence saying why the builder made a recorded decision (the stepper's caption).
std::string explain(BuildDecision decision, int max_leaf_size);

}  // namespace accelviz
