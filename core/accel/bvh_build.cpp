// The BVH build's driver: one decision per node (leaf or split, and which split),
// an explicit work stack, the leaf-order copy, statistics and notes. The builders
// that propose splits live one per file behind bvh_splitter.h.
#include "core/accel/bvh_build.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <optional>

#include "core/accel/bvh_splitter.h"
#include "core/accel/sah.h"
#include "core/util/prefetch.h"

namespace accelviz {
namespace {

using namespace bvh_detail;

// ---------------------------------------------------------------------------
// [SECTION] The driver: one decision per node, explicit work stack
// ---------------------------------------------------------------------------

std::unique_ptr<Splitter> make_splitter(const BvhConfig& config, PrimRefs refs) {
    const SahCostModel model{config.cost_trav, config.cost_isect};
    switch (config.builder) {
        case BvhBuilder::Midpoint: return make_midpoint_splitter(std::move(refs));
        case BvhBuilder::Median: return make_median_splitter(std::move(refs));
        case BvhBuilder::SahSweep: return make_sweep_sah_splitter(std::move(refs), model);
        case BvhBuilder::SahBinned: break;
    }
    return make_binned_sah_splitter(std::move(refs), config.bins, model);
}

/// How many halvings turn `count` triangles into leaves of at most `max_leaf` (0 if it fits).
uint32_t levels_needed(uint32_t count, uint32_t max_leaf) {
    uint32_t levels = 0;
    for (; count > max_leaf; count = count - count / 2) ++levels;
    return levels;
}

bool is_leaf(BuildDecision d) {
    return d == BuildDecision::LeafFits || d == BuildDecision::LeafCheaper ||
           d == BuildDecision::LeafNoSeparatingPlane || d == BuildDecision::LeafDepthLimit;
}

bool splits_in_half(BuildDecision d) {
    return d == BuildDecision::SplitInHalfCentroidsEqual || d == BuildDecision::SplitInHalfDepthBudget;
}

/// A node being decided: its triangles' range, its depth and its two boxes.
struct NodeToDecide {
    Range range;
    uint32_t depth;
    const Aabb& bounds;
    const Aabb& centroid_bounds;
};

/// Leaf or split, and which split (see BuildDecision). `choice` is filled when a split was searched.
/// Depth budget: every node satisfies depth + levels_needed(count) <= kBvhMaxDepth (true at the
/// root for any 32-bit count). A split by index keeps it; the builder's own split is taken
/// only if its larger child keeps it too. So no leaf is ever deeper than kBvhMaxDepth.
BuildDecision decide(Splitter& splitter, const NodeToDecide& node, const BvhConfig& config, SplitChoice& choice,
                     BuildStep* step) {
    const Range range = node.range;
    const uint32_t depth = node.depth;
    const SahCostModel model{config.cost_trav, config.cost_isect};
    const uint32_t n = range.count();
    const bool fits = n <= uint32_t(config.max_leaf_size);
    if (n == 1 || (fits && !splitter.uses_sah())) return BuildDecision::LeafFits;

    choice = splitter.find_split(range, node.bounds, node.centroid_bounds, step);
    const uint32_t larger_child = std::max(choice.left_count, n - choice.left_count);
    const bool within_budget =
        choice.found && depth + 1 + levels_needed(larger_child, uint32_t(config.max_leaf_size)) <= kBvhMaxDepth;

    if (!splitter.uses_sah()) {
        if (!choice.found) return BuildDecision::SplitInHalfCentroidsEqual;
        if (!within_budget) return BuildDecision::SplitInHalfDepthBudget;
        return choice.median_fallback ? BuildDecision::SplitMedianFallback : BuildDecision::Split;
    }
    // SAH: split only if it is cheaper than the leaf, or if the leaf would not fit.
    if (choice.found && choice.cost < model.leaf_cost(n)) {
        if (within_budget) return BuildDecision::Split;
        return fits ? BuildDecision::LeafDepthLimit : BuildDecision::SplitInHalfDepthBudget;
    }
    if (fits) return choice.found ? BuildDecision::LeafCheaper : BuildDecision::LeafNoSeparatingPlane;
    if (!choice.found) return BuildDecision::SplitInHalfCentroidsEqual;
    return within_budget ? BuildDecision::SplitForcedBySize : BuildDecision::SplitInHalfDepthBudget;
}

/// Fills bvh.triangles in leaf order: triangles[k] = mesh.triangle(prim_ids[k]). The ids
/// jump around the mesh, so each triangle's index triple and corners are a cache miss of
/// their own; the loop asks for them some triangles ahead (the index triple first, its
/// corners once the triple has had time to arrive) so the misses overlap instead of
/// following each other.
void copy_triangles_in_leaf_order(const Mesh& mesh, Bvh& bvh) {
    constexpr size_t kTriplesAhead = 16, kCornersAhead = 8;
    const auto& ids = bvh.prim_ids;
    const size_t n = ids.size();
    bvh.triangles.reserve(n);
    for (size_t k = 0; k < n; ++k) {
        if (k + kTriplesAhead < n) prefetch(&mesh.indices[ids[k + kTriplesAhead]]);
        if (k + kCornersAhead < n) {
            for (uint32_t corner : mesh.indices[ids[k + kCornersAhead]]) prefetch(&mesh.positions[corner]);
        }
        bvh.triangles.push_back(mesh.triangle(ids[k]));
    }
}

/// Depths, leaf sizes and SAH cost of the tree, gathered as the build makes its nodes
/// (parents before children, left subtree first).
class TreeStats {
public:
    TreeStats(const SahCostModel& model, uint32_t max_leaf_size) : model_(model), max_leaf_size_(max_leaf_size) {}

    /// Every node, the root first: its share of the SAH cost (its hit probability times
    /// C_trav for an interior node, times count · C_isect for a leaf).
    void add_node(const Aabb& bounds, uint32_t depth, uint32_t leaf_count, BvhBuildStats& stats) {
        if (depth == 0) root_area_ = bounds.area();
        const double p = SahCostModel::hit_probability(bounds.area(), root_area_);
        if (leaf_count == 0) {
            sah_ += p * model_.cost_trav;
            return;
        }
        ++stats.leaves;
        depth_sum_ += depth;
        stats.max_depth = std::max(stats.max_depth, depth);
        if (stats.leaf_size_histogram.size() <= leaf_count) stats.leaf_size_histogram.resize(leaf_count + 1, 0);
        ++stats.leaf_size_histogram[leaf_count];
        if (leaf_count > max_leaf_size_) ++stats.leaves_over_limit;
        sah_ += p * leaf_count * model_.cost_isect;
    }
    /// Totals and memory, once the tree is complete.
    void finish(const Bvh& bvh, BvhBuildStats& stats) const {
        stats.nodes = uint32_t(bvh.nodes.size());
        stats.memory_bytes = bvh.nodes.size() * sizeof(BvhNode) + bvh.prim_ids.size() * sizeof(uint32_t) +
                             bvh.triangles.size() * sizeof(Triangle);
        if (stats.leaves == 0) return;
        stats.avg_leaf_depth = depth_sum_ / stats.leaves;
        stats.sah_cost = sah_;
    }

private:
    SahCostModel model_;
    uint32_t max_leaf_size_;
    float root_area_ = 0;
    double depth_sum_ = 0, sah_ = 0;
};

/// One sentence per unusual decision, so the stats say why the tree looks as it does.
void write_notes(const BvhConfig& config, BvhBuildStats& stats) {
    auto note = [&](BuildDecision d, const std::string& what) {
        if (const uint32_t n = stats.count(d)) stats.notes.push_back(std::to_string(n) + " " + what);
    };
    if (stats.triangles == 0) stats.notes.push_back("empty scene: the tree has no nodes and every ray misses");
    note(BuildDecision::SplitInHalfCentroidsEqual,
         "nodes split in half by index: all their triangles' centroids are equal, so no plane separates them");
    note(BuildDecision::LeafNoSeparatingPlane,
         "leaves made because all their triangles' centroids are equal (no plane separates them)");
    note(BuildDecision::SplitMedianFallback,
         "nodes split at the median: the middle of their centroid bounds rounded onto one end (bounds a few floats wide)");
    note(BuildDecision::SplitForcedBySize, "nodes split although a leaf was cheaper by the SAH: a leaf may hold at most " +
                                               std::to_string(config.max_leaf_size) + " triangles");
    note(BuildDecision::SplitInHalfDepthBudget,
         "nodes split in half by index: the builder's split could have made the tree deeper than " +
             std::to_string(kBvhMaxDepth) + " levels");
    note(BuildDecision::LeafDepthLimit,
         "leaves made because a split would have made the tree deeper than " + std::to_string(kBvhMaxDepth) + " levels");
    if (stats.leaves_over_limit)
        stats.notes.push_back(std::to_string(stats.leaves_over_limit) + " leaves larger than the limit of " +
                              std::to_string(config.max_leaf_size));
}

}  // namespace

Expected<Bvh> build_bvh(const Mesh& mesh, const BvhConfig& requested, BuildRecorder* recorder) {
    if (auto err = validate(requested)) return *err;
    const auto start = std::chrono::steady_clock::now();
    Bvh bvh;
    bvh.build_config = requested;
    const BvhConfig& config = bvh.build_config;
    const SahCostModel model{config.cost_trav, config.cost_isect};
    BvhBuildStats& stats = bvh.build_stats;
    const auto n = uint32_t(mesh.triangle_count());
    stats.triangles = n;

    TreeStats tree_stats(model, uint32_t(config.max_leaf_size));
    if (n > 0) {
        PrimRefs refs;
        refs.reserve(n);
        for (uint32_t i = 0; i < n; ++i) refs.push_back(make_prim_ref(mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2), i));
        std::unique_ptr<Splitter> splitter = make_splitter(config, std::move(refs));

        bvh.nodes.reserve(2 * size_t(n) - 1);  // a binary tree with at most n leaves
        bvh.nodes.emplace_back();
        /// A node still to build; its boxes come along when the parent's partition measured them.
        struct Task {
            uint32_t node, begin, end, depth;
            bool measured = false;
            Aabb bounds, centroid_bounds;
        };
        // The left child goes straight on as the next task; the right one waits on the
        // stack: left subtrees are built (and laid out) first, depth first.
        std::vector<Task> work;
        std::optional<Task> left_next = Task{0, 0, n, 0, false, {}, {}};
        while (left_next || !work.empty()) {
            Task task;
            if (left_next) {
                task = *left_next;
                left_next.reset();
            } else {
                task = work.back();
                work.pop_back();
            }
            const Range range{task.begin, task.end};
            Aabb bounds = task.bounds, centroid_bounds = task.centroid_bounds;
            if (!task.measured) splitter->measure(range, bounds, centroid_bounds);
            bvh.nodes[task.node].bounds = bounds;

            std::optional<BuildStep> step;
            if (recorder) step.emplace();
            SplitChoice choice;
            const BuildDecision decision =
                decide(*splitter, {range, task.depth, bounds, centroid_bounds}, config, choice,
                       step && recorder->record_candidates ? &*step : nullptr);
            ++stats.decisions[size_t(decision)];

            if (is_leaf(decision)) {
                bvh.nodes[task.node].first = range.begin;
                bvh.nodes[task.node].count = range.count();
                tree_stats.add_node(bounds, task.depth, range.count(), stats);
            } else {
                tree_stats.add_node(bounds, task.depth, 0, stats);
                ChildBounds children;
                const uint32_t mid = splits_in_half(decision) ? splitter->partition_in_half(range)
                                                              : splitter->partition(range, choice, children);
                if (!children.filled) {
                    splitter->measure({range.begin, mid}, children.bounds[0], children.centroid_bounds[0]);
                    splitter->measure({mid, range.end}, children.bounds[1], children.centroid_bounds[1]);
                }
                const auto left = uint32_t(bvh.nodes.size());
                bvh.nodes.emplace_back();
                bvh.nodes.emplace_back();
                bvh.nodes[task.node].first = left;
                bvh.nodes[task.node].count = 0;
                work.push_back({left + 1, mid, range.end, task.depth + 1, true, children.bounds[1],
                                children.centroid_bounds[1]});
                left_next = Task{left, range.begin, mid, task.depth + 1, true, children.bounds[0],
                                 children.centroid_bounds[0]};
                if (step) {
                    step->split_cost = model.split_cost(bounds.area(), children.bounds[0].area(), mid - range.begin,
                                                        children.bounds[1].area(), range.end - mid);
                    step->left_count = mid - range.begin;
                    if (!splits_in_half(decision)) {
                        step->axis = choice.axis;
                        step->split_position = choice.position;
                    }
                }
            }
            if (step) {
                step->node = task.node;
                step->depth = task.depth;
                step->first = range.begin;
                step->count = range.count();
                step->bounds = bounds;
                step->centroid_bounds = centroid_bounds;
                step->decision = decision;
                step->leaf_cost = model.leaf_cost(range.count());
                recorder->steps.push_back(std::move(*step));
            }
        }
        // Leaf order: the triangles of each leaf next to each other, as the traversal reads them.
        bvh.prim_ids.resize(n);
        for (uint32_t k = 0; k < n; ++k) bvh.prim_ids[k] = splitter->prim_id(k);
        // The build records go before the leaf-order copy is made, so the two are never in
        // memory together (a lower peak).
        splitter.reset();
        copy_triangles_in_leaf_order(mesh, bvh);
    }

    tree_stats.finish(bvh, stats);
    write_notes(config, stats);
    stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace accelviz
