#include "core/accel/bvh_config.h"

#include <algorithm>
#include <cmath>

namespace accelviz {

std::string_view to_string(BvhBuilder builder) {
    switch (builder) {
        case BvhBuilder::Midpoint: return "midpoint";
        case BvhBuilder::Median: return "median";
        case BvhBuilder::SahSweep: return "sah-sweep";
        case BvhBuilder::SahBinned: return "sah-binned";
    }
    return "unknown";
}

std::string_view to_string(BvhTraversal traversal) {
    switch (traversal) {
        case BvhTraversal::Ordered: return "ordered";
        case BvhTraversal::Unordered: return "unordered";
    }
    return "unknown";
}

std::string_view to_string(BuildDecision decision) {
    switch (decision) {
        case BuildDecision::LeafFits: return "leaf_fits";
        case BuildDecision::LeafCheaper: return "leaf_cheaper";
        case BuildDecision::LeafNoSeparatingPlane: return "leaf_no_separating_plane";
        case BuildDecision::LeafDepthLimit: return "leaf_depth_limit";
        case BuildDecision::Split: return "split";
        case BuildDecision::SplitForcedBySize: return "split_forced_by_size";
        case BuildDecision::SplitMedianFallback: return "split_median_fallback";
        case BuildDecision::SplitInHalfCentroidsEqual: return "split_in_half_centroids_equal";
        case BuildDecision::SplitInHalfDepthBudget: return "split_in_half_depth_budget";
    }
    return "unknown";
}

const std::vector<std::string>& bvh_builder_names() {
    static const std::vector<std::string> names = {"midpoint", "median", "sah-sweep", "sah-binned"};
    return names;
}

const std::vector<std::string>& bvh_traversal_names() {
    static const std::vector<std::string> names = {"ordered", "unordered"};
    return names;
}

std::optional<BvhBuilder> parse_bvh_builder(std::string_view name) {
    for (BvhBuilder b : {BvhBuilder::Midpoint, BvhBuilder::Median, BvhBuilder::SahSweep, BvhBuilder::SahBinned})
        if (to_string(b) == name) return b;
    return std::nullopt;
}

std::optional<BvhTraversal> parse_bvh_traversal(std::string_view name) {
    for (BvhTraversal t : {BvhTraversal::Ordered, BvhTraversal::Unordered})
        if (to_string(t) == name) return t;
    return std::nullopt;
}

std::optional<Error> validate(const BvhConfig& config) {
    if (config.bins < kBvhMinBins || config.bins > kBvhMaxBins)
        return Error{"--bins must be between " + std::to_string(kBvhMinBins) + " and " + std::to_string(kBvhMaxBins) +
                     " (got " + std::to_string(config.bins) + ")"};
    if (config.max_leaf_size < 1 || config.max_leaf_size > kBvhMaxLeafSize)
        return Error{"--leaf-size must be between 1 and " + std::to_string(kBvhMaxLeafSize) + " (got " +
                     std::to_string(config.max_leaf_size) + ")"};
    if (!std::isfinite(config.cost_trav) || config.cost_trav < 0.0f)
        return Error{"--cost-trav must be a finite number >= 0 (got " + std::to_string(config.cost_trav) + ")"};
    if (!std::isfinite(config.cost_isect) || config.cost_isect <= 0.0f)
        return Error{"--cost-isect must be a finite number > 0 (got " + std::to_string(config.cost_isect) + ")"};
    if (config.width != 2 && config.width != 4 && config.width != 8)
        return Error{"--bvh-width must be 2, 4 or 8 (got " + std::to_string(config.width) + ")"};
    if (config.leaf_lanes != 1 && config.leaf_lanes != 4)
        return Error{"leaf lanes must be 1 or 4 (got " + std::to_string(config.leaf_lanes) + ")"};
    return std::nullopt;
}

nlohmann::json to_json(const BvhConfig& config) {
    return {{"builder", to_string(config.builder)},
            {"bins", config.bins},
            {"max_leaf_size", config.max_leaf_size},
            {"cost_trav", config.cost_trav},
            {"cost_isect", config.cost_isect},
            {"width", config.width},
            {"leaf_lanes", config.leaf_lanes}};
}

nlohmann::json to_json(const BvhBuildStats& stats) {
    nlohmann::json decisions = nlohmann::json::object();
    for (int d = 0; d < kBuildDecisionCount; ++d)
        decisions[std::string(to_string(BuildDecision(d)))] = stats.decisions[size_t(d)];
    nlohmann::json j = {{"triangles", stats.triangles},
            {"nodes", stats.nodes},
            {"leaves", stats.leaves},
            {"max_depth", stats.max_depth},
            {"avg_leaf_depth", stats.avg_leaf_depth},
            {"leaf_size_histogram", stats.leaf_size_histogram},
            {"sah_cost", stats.sah_cost},
            {"memory_bytes", stats.memory_bytes},
            {"build_ms", stats.build_ms},
            {"decisions", decisions},
            {"leaves_over_limit", stats.leaves_over_limit},
            {"notes", stats.notes}};
    if (stats.refit_ms > 0) j["refit_ms"] = stats.refit_ms;  // only a refitted tree has one
    return j;
}

}  // namespace accelviz
