#pragma once
/// The SAH chart of one KD tree node, for the construction stepper (lecture: the
/// KD tree built plane by plane): every candidate plane per axis with its cost,
/// the empty-space bonus included, the leaf cost N·C_isect, and the cheapest plane.
/// The node's references are made again as the build made them (clipped cell by
/// cell down the path from the root) and swept by the builder's own sweep
/// (kd_sah.h), so under the tree's costs the cheapest plane is the tree's plane.

#include <array>
#include <cstdint>
#include <vector>

#include "core/accel/kd_tree.h"

namespace accelviz {

struct KdSahChartAxis {
    float lo = 0, hi = 0;            ///< the cell along this axis: the chart's x range
    std::vector<float> positions;    ///< candidate planes, in increasing position
    std::vector<float> costs;        ///< their SAH costs
    std::vector<uint32_t> below, above;  ///< references each side would hold
    size_t candidates = 0;           ///< every plane the builder weighs on this axis
    /// Only some are listed: each the cheapest of a run of neighbours (the minimum is kept).
    bool subsampled = false;
};

struct KdSahChart {
    uint32_t node = 0;
    uint32_t count = 0;              ///< the node's references
    Aabb cell;
    KdConfig config;                 ///< the costs the chart weighs with
    std::array<KdSahChartAxis, 3> axes;
    float leaf_cost = 0;             ///< N · C_isect (N counted in tests, kd_tests)
    int best_axis = -1;              ///< -1: no plane lies strictly inside the cell
    float best_position = 0;
    float best_cost = 0;
    uint32_t best_below = 0, best_above = 0;
};

/// The chart of `node` of `tree` (built over `mesh`) under `config`'s C_trav, C_isect
/// and empty_bonus (the references are the tree's own, whatever the costs).
/// `max_points`: list at most this many candidates per axis (0: all).
KdSahChart kd_sah_chart(const Mesh& mesh, const KdTree& tree, uint32_t node, const KdConfig& config,
                        size_t max_points = 0);

}  // namespace accelviz
