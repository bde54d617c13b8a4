#pragma once
/// What a BVH is built with (BvhConfig) and what its build reports (BvhBuildStats).
/// Plain data; the CLI flags, the Structure panel and bench read and write these.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/accel/sah.h"
#include "core/util/expected.h"

namespace accelviz {

/// How the builder chooses where to split a node (lecture: 构建层次包围盒的启发式规则, SAH).
enum class BvhBuilder : uint8_t {
    Midpoint,   ///< heuristic 1: longest axis of the centroid bounds, split at its middle
    Median,     ///< heuristic 2: longest axis, split at the median triangle (equal counts)
    SahSweep,   ///< full SAH: every centroid position on all three axes (prefix/suffix bounds)
    SahBinned,  ///< binned SAH: B buckets per axis, B - 1 candidate planes each (Wald 2007)
};

/// Which closest-hit traversal the BVH runs (lecture: 基于 BVH 的最近点查询).
enum class BvhTraversal : uint8_t {
    Ordered,    ///< algorithm 2: nearest child first, skip nodes beyond the closest hit
    Unordered,  ///< algorithm 1: left then right, no ordering, no pruning by the closest hit
};

std::string_view to_string(BvhBuilder builder);
std::string_view to_string(BvhTraversal traversal);
/// The names accepted on the command line: "midpoint", "median", "sah-sweep", "sah-binned".
const std::vector<std::string>& bvh_builder_names();
/// "ordered", "unordered".
const std::vector<std::string>& bvh_traversal_names();
std::optional<BvhBuilder> parse_bvh_builder(std::string_view name);
std::optional<BvhTraversal> parse_bvh_traversal(std::string_view name);

/// Deepest leaf a builder may make (root = depth 0). Traversals keep an explicit
/// stack of kBvhStackSize entries and push at most one entry per level, so this
/// bound is what makes the fixed-size stack safe.
inline constexpr uint32_t kBvhMaxDepth = 63;
inline constexpr int kBvhStackSize = 64;

/// The ranges of the build parameters: validate() checks them, and the command line's
/// checks and the window's sliders read them from here.
inline constexpr int kBvhMinBins = 2, kBvhMaxBins = 64;
inline constexpr int kBvhMaxLeafSize = 255;  ///< a leaf's count must fit the node's bookkeeping

/// Build parameters. Every field has the default the lecture's discussion suggests.
struct BvhConfig {
    BvhBuilder builder = BvhBuilder::SahBinned;  ///< how nodes are split
    int bins = 16;                               ///< sah-binned: buckets per axis, kBvhMinBins..kBvhMaxBins (lecture: B < 32)
    int max_leaf_size = 4;                       ///< a leaf holds at most this many triangles, 1..kBvhMaxLeafSize
    float cost_trav = 1.0f;                      ///< SAH: C_trav, cost of stepping through an interior node, >= 0
    float cost_isect = 1.0f;                     ///< SAH: C_isect, cost of one ray–triangle test, > 0
    /// Children per node: 2 (the lecture's binary tree), or 4 or 8: the binary tree
    /// collapsed into a wide one whose children are tested together (wide_bvh.h).
    /// build_bvh() always builds the binary tree; build_accelerator() collapses it.
    int width = 2;
    /// Triangles a leaf tests together, as the SAH counts them (sah.h): 1 for the
    /// lecture's tree; 4 for a tree to be collapsed, whose leaves the wide BVH tests
    /// four at a time (build_accelerator sets it from the width).
    int leaf_lanes = 1;

    SahCostModel sah_model() const { return {cost_trav, cost_isect, uint32_t(leaf_lanes)}; }

    bool operator==(const BvhConfig&) const = default;
};

/// A one-line error if a field is out of range (names the CLI flag). The builder and
/// the SAH chart refuse a config this refuses.
std::optional<Error> validate(const BvhConfig& config);

/// Why the builder made a node a leaf or split it the way it did. Every node
/// gets exactly one decision; BvhBuildStats counts them.
enum class BuildDecision : uint8_t {
    LeafFits,                   ///< midpoint/median: at most max_leaf_size triangles
    LeafCheaper,                ///< SAH: no split is cheaper than the leaf, and the leaf fits
    LeafNoSeparatingPlane,      ///< SAH: no plane separates the centroids, and the leaf fits
    LeafDepthLimit,             ///< at kBvhMaxDepth no split is allowed (the depth budget made sure the leaf fits)
    Split,                      ///< the builder's own choice (heuristic plane, or SAH's cheapest split)
    SplitForcedBySize,          ///< SAH: the leaf is cheaper but would exceed max_leaf_size: cheapest split taken
    SplitMedianFallback,        ///< midpoint: the middle plane left one side empty (rounding): median split instead
    SplitInHalfCentroidsEqual,  ///< no plane separates the centroids: the index range is split in half
    SplitInHalfDepthBudget,     ///< the builder's split could make the tree deeper than kBvhMaxDepth: split in half
};
inline constexpr int kBuildDecisionCount = 9;
std::string_view to_string(BuildDecision decision);

/// What the build produced. memory_bytes counts nodes, prim_ids and the
/// leaf-ordered triangle copy.
struct BvhBuildStats {
    uint32_t triangles = 0;
    uint32_t nodes = 0;            ///< interior + leaves (0 for an empty scene)
    uint32_t leaves = 0;
    uint32_t max_depth = 0;        ///< depth of the deepest leaf, root = 0
    double avg_leaf_depth = 0;     ///< mean depth over leaves
    std::vector<uint32_t> leaf_size_histogram;  ///< [k] = number of leaves holding k triangles
    double sah_cost = 0;           ///< the tree's SAH cost: Σ interior S/S_root·C_trav + Σ leaf S/S_root·N·C_isect (N in tests: leaf_lanes)
    uint64_t memory_bytes = 0;
    double build_ms = 0;           ///< wall time of build_bvh, one thread
    double refit_ms = 0;           ///< wall time of the last refit_bvh (0: not refitted; bvh_build.h)
    std::array<uint32_t, kBuildDecisionCount> decisions{};  ///< [BuildDecision] = nodes it decided
    uint32_t leaves_over_limit = 0;  ///< leaves holding more than max_leaf_size triangles (explained in notes)
    /// One sentence per unusual decision, e.g. "31 nodes split in half by index:
    /// all their centroids are equal, so no plane separates them".
    std::vector<std::string> notes;

    uint32_t count(BuildDecision d) const { return decisions[size_t(d)]; }
};

nlohmann::json to_json(const BvhConfig& config);
nlohmann::json to_json(const BvhBuildStats& stats);

}  // namespace accelviz
