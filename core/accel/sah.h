#pragma once
/// The surface area heuristic (SAH), the lecture's cost model for a BVH
/// (如何衡量划分的质量？). A leaf holding N triangles costs
///     C_leaf = N · C_isect
/// and splitting a node N into children A and B is expected to cost
///     C_split = C_trav + S_A/S_N · N_A · C_isect + S_B/S_N · N_B · C_isect
/// where S is a box's surface area: S_A/S_N is the probability that a random
/// ray that hits N's box also hits A's box (convex A inside convex N).
/// Costs are in units of the caller's choosing; only their ratios matter.
///
/// A tree whose leaves test their triangles L at a time (the wide BVH's leaves, four
/// lanes: geometry/triangle_lanes.h) counts a leaf's tests, not its triangles: N
/// becomes ceil(N / L) in both formulas, as Embree's builders count blocks of four.
/// L = 1 is the lecture's model.

#include <bit>
#include <algorithm>
#include <cstdint>
#include <limits>

namespace accelviz {

/// ceil(count / lanes): the tests a leaf of `count` triangles makes when it tests
/// `lanes` triangles together. Every SAH here (the BVH's, the KD tree's) counts this.
/// Lanes are 1, 4 or 8: a shift, not a division (a sweep asks twice per candidate).
constexpr uint64_t leaf_tests(uint64_t count, uint64_t lanes) {
    return std::has_single_bit(lanes) ? (count + lanes - 1) >> std::countr_zero(lanes) : (count + lanes - 1) / lanes;
}

struct SahCostModel {
    float cost_trav = 1.0f;   ///< C_trav: one interior-node step (its box tests), > 0 not required
    float cost_isect = 1.0f;  ///< C_isect: one ray–triangle test, > 0
    uint32_t leaf_lanes = 1;  ///< L: triangles a leaf tests together

    /// ceil(count / L): the tests a leaf of `count` triangles makes.
    uint32_t tests(uint32_t count) const { return uint32_t(leaf_tests(count, leaf_lanes)); }

    /// S_child / S_parent. A parent of zero area (all its triangles are points
    /// or lie on one line) is hit only by rays that hit every child, so 0/0 is 1.
    static float hit_probability(float area_child, float area_parent) {
        return area_parent > 0.0f ? area_child / area_parent : 1.0f;
    }

    /// C_leaf = N · C_isect (N counted in tests).
    float leaf_cost(uint32_t count) const { return float(tests(count)) * cost_isect; }

    /// C_split = C_trav + S_A/S_N · N_A · C_isect + S_B/S_N · N_B · C_isect (N counted in tests).
    float split_cost(float area_parent, float area_a, uint32_t count_a, float area_b, uint32_t count_b) const {
        return cost_trav + (hit_probability(area_a, area_parent) * float(tests(count_a)) +
                            hit_probability(area_b, area_parent) * float(tests(count_b))) * cost_isect;
    }
};

/// The larger of a split's two sides (of `count` triangles): the smaller, the more even.
inline uint32_t larger_side(uint32_t left_count, uint32_t count) { return std::max(left_count, count - left_count); }

/// How every SAH search here picks among candidate planes of a node of `count`
/// triangles: a cheaper plane wins; of two that cost exactly the same, the one that
/// divides the triangles more evenly (its larger side is smaller); of two equally
/// even, the one found first (first axis, then first plane). A plane of infinite
/// cost (one side empty) never wins.
///
/// Why the evenness rule: in the lecture's tricky case "all boxes equal" (棘手的情况)
/// every child box is the parent's box, so every plane costs C_trav + N · C_isect and
/// the SAH has no preference. Taking the first plane would peel a few triangles off
/// per level (a tree 63 deep for 1000 triangles); the most even plane halves them, as
/// the median heuristic would, and the tree stays about log2 N deep. Where planes
/// rarely tie (scanned meshes) the trees do not change; architectural scenes have
/// exact ties (walls of equal boxes) and get shallower trees of about the same
/// quality (figures in docs/performance.md).
inline bool is_better_split(float cost, uint32_t left_count, float best_cost, uint32_t best_left_count,
                            uint32_t count) {
    if (!(cost <= best_cost)) return false;  // dearer (or NaN): most candidates, one comparison
    if (cost < best_cost) return true;
    if (!(cost < std::numeric_limits<float>::infinity())) return false;
    return larger_side(left_count, count) < larger_side(best_left_count, count);
}

}  // namespace accelviz
