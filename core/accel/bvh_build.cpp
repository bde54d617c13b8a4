// The BVH build's driver: one decision per node (leaf or split, and which split),
// big subtrees built in parallel and small ones depth first, the leaf-order copy,
// statistics and notes. The builders that propose splits live one per file behind
// bvh_splitter.h.
#include "core/accel/bvh_build.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <memory>
#include <optional>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "core/accel/bvh_splitter.h"
#include "core/accel/sah.h"

namespace accelviz {
namespace {

using namespace bvh_detail;

// ---------------------------------------------------------------------------
// [SECTION] The driver: one decision per node, explicit work stack
// ---------------------------------------------------------------------------

std::unique_ptr<Splitter> make_splitter(const BvhConfig& config, PrimRefs refs) {
    const SahCostModel model = config.sah_model();
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
    const SahCostModel model = config.sah_model();
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

// ---------------------------------------------------------------------------
// [SECTION] Building subtrees, in parallel where they are big
// ---------------------------------------------------------------------------

/// Nodes of this many triangles or more have their two subtrees built in parallel
/// (oneTBB tasks); smaller ones are built depth first by one task. A fixed size, not
/// a share of the threads, so the same subtrees are built the same way on any number
/// of threads: the tree is the same bit for bit.
constexpr uint32_t kParallelSubtree = 4096;
/// Triangles per chunk in the build's parallel loops over all triangles.
constexpr size_t kParallelChunk = size_t(1) << 14;

using DecisionCounts = std::array<uint32_t, kBuildDecisionCount>;
using NodeArray = decltype(Bvh::nodes);

/// A node still to build; its boxes come along when the parent's partition measured them.
struct Task {
    uint32_t node, begin, end, depth;
    bool measured = false;
    Aabb bounds, centroid_bounds;
};

/// What deciding one node gave: a leaf, or a split with its two children still to build.
struct Decided {
    bool leaf = true;
    Task left, right;  ///< for a split; their `node` is left to the caller
};

/// Decides `task`'s node and writes it to `node` (its box; for a leaf its triangle
/// range; for a split count 0, the caller sets `first` to the left child's index).
/// A split reorders the node's range. With a recorder, the decision is appended to
/// it under the node index task.node.
Decided decide_node(Splitter& splitter, const Task& task, const BvhConfig& config, BvhNode& node,
                    DecisionCounts& counts, BuildRecorder* recorder) {
    const SahCostModel model = config.sah_model();
    const Range range{task.begin, task.end};
    Aabb bounds = task.bounds, centroid_bounds = task.centroid_bounds;
    if (!task.measured) splitter.measure(range, bounds, centroid_bounds);
    node.bounds = bounds;

    std::optional<BuildStep> step;
    if (recorder) step.emplace();
    SplitChoice choice;
    const BuildDecision decision = decide(splitter, {range, task.depth, bounds, centroid_bounds}, config, choice,
                                          step && recorder->record_candidates ? &*step : nullptr);
    ++counts[size_t(decision)];

    Decided result;
    if (is_leaf(decision)) {
        node.first = range.begin;
        node.count = range.count();
    } else {
        node.count = 0;
        ChildBounds children;
        const uint32_t mid = splits_in_half(decision) ? splitter.partition_in_half(range)
                                                      : splitter.partition(range, choice, children);
        if (!children.filled) {
            splitter.measure({range.begin, mid}, children.bounds[0], children.centroid_bounds[0]);
            splitter.measure({mid, range.end}, children.bounds[1], children.centroid_bounds[1]);
        }
        result.leaf = false;
        result.left = {0, range.begin, mid, task.depth + 1, true, children.bounds[0], children.centroid_bounds[0]};
        result.right = {0, mid, range.end, task.depth + 1, true, children.bounds[1], children.centroid_bounds[1]};
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
    return result;
}

/// Where the build keeps the nodes of its depth-first parts until their places in the
/// tree are known: one block of at most 2N - 1 nodes (a binary tree over N non-empty
/// leaves has no more), handed out front to back as parts finish. Which part lands
/// where depends on the threads' timing, but each part is then copied to its one
/// place in the tree, so the tree does not. Not initialized: a slot is written before
/// it is read; only the used front is touched.
class NodeStore {
public:
    explicit NodeStore(uint32_t triangles) : size_(2 * size_t(triangles) - 1), nodes_(Allocator().allocate(size_)) {}
    ~NodeStore() { Allocator().deallocate(nodes_, size_); }
    NodeStore(const NodeStore&) = delete;
    NodeStore& operator=(const NodeStore&) = delete;
    /// Keeps a copy of `nodes`; returns where it is.
    const BvhNode* keep(const std::vector<BvhNode>& nodes) {
        BvhNode* at = nodes_ + used_.fetch_add(nodes.size());
        std::copy(nodes.begin(), nodes.end(), at);
        return at;
    }

private:
    using Allocator = LargeArrayAllocator<BvhNode>;
    size_t size_;
    BvhNode* nodes_;
    std::atomic<size_t> used_{0};
};

/// Builds the subtree of `root` depth first into `nodes`: the subtree's root at [0]
/// and its descendants after it, with child indices local to `nodes`. The layout: a
/// split node's two children side by side at the next free index, then the left
/// child's descendants, then the right child's (the left child goes straight on as
/// the next task, the right one waits on the stack).
void build_depth_first(Splitter& splitter, Task root, const BvhConfig& config, std::vector<BvhNode>& nodes,
                       DecisionCounts& counts, BuildRecorder* recorder, const WorkProgress* progress) {
    root.node = 0;
    nodes.assign(1, BvhNode{});
    std::vector<Task> work;
    std::optional<Task> left_next = root;
    while (left_next || !work.empty()) {
        if (cancelled(progress)) return;  // the caller drops the unfinished tree
        Task task;
        if (left_next) {
            task = *left_next;
            left_next.reset();
        } else {
            task = work.back();
            work.pop_back();
        }
        BvhNode node;
        Decided decided = decide_node(splitter, task, config, node, counts, recorder);
        if (!decided.leaf) {
            node.first = uint32_t(nodes.size());
            decided.left.node = node.first;
            decided.right.node = node.first + 1;
            nodes.resize(nodes.size() + 2);
            work.push_back(decided.right);
            left_next = decided.left;
        }
        nodes[task.node] = node;
    }
}

/// A subtree as the build left it: built depth first by one task (its nodes kept in
/// the store, `left` and `right` empty), or, when big, its root decided here and its
/// two children's subtrees built in parallel.
struct Subtree {
    const BvhNode* nodes = nullptr;  ///< built depth first: in the store
    uint32_t node_count = 0;         ///< built depth first: how many
    BvhNode root;                    ///< built in parallel: the root
    std::unique_ptr<Subtree> left, right;
    DecisionCounts counts{};
};

/// Counts the subtree's triangles as placed in leaves once it is built (`progress`:
/// units are triangles); stops early, leaving it unfinished, once `progress` is cancelled.
std::unique_ptr<Subtree> build_subtree(Splitter& splitter, const Task& task, const BvhConfig& config,
                                       NodeStore& store, WorkProgress* progress) {
    auto subtree = std::make_unique<Subtree>();
    if (cancelled(progress)) return subtree;
    if (task.end - task.begin < kParallelSubtree) {
        thread_local std::vector<BvhNode> nodes;  // reused: it stays in the cache
        build_depth_first(splitter, task, config, nodes, subtree->counts, nullptr, progress);
        subtree->nodes = store.keep(nodes);
        subtree->node_count = uint32_t(nodes.size());
        advance(progress, task.end - task.begin);
        return subtree;
    }
    const Decided decided = decide_node(splitter, task, config, subtree->root, subtree->counts, nullptr);
    if (decided.leaf) {
        subtree->nodes = &subtree->root;
        subtree->node_count = 1;
        advance(progress, task.end - task.begin);
        return subtree;
    }
    // The two children work on disjoint ranges of the records: one keeps this splitter,
    // the other gets a fork.
    const std::unique_ptr<Splitter> fork = splitter.fork();
    tbb::parallel_invoke([&] { subtree->left = build_subtree(splitter, decided.left, config, store, progress); },
                         [&] { subtree->right = build_subtree(*fork, decided.right, config, store, progress); });
    return subtree;
}

/// A depth-first part of the tree and where its nodes go: its root to `slot`, the
/// rest from `next` on.
struct Placement {
    const BvhNode* nodes;
    uint32_t count, slot, next;
};

/// Lays `subtree` out as build_depth_first would have over the whole tree: its root at
/// `slot`, its descendants from `next` on. Nodes built in parallel are written at
/// once; depth-first parts are listed in `parts` to be copied after. Returns the
/// first index after the subtree. Adds its decision counts to `counts`.
uint32_t place(const Subtree& subtree, uint32_t slot, uint32_t next, NodeArray& nodes, std::vector<Placement>& parts,
               DecisionCounts& counts) {
    for (size_t d = 0; d < counts.size(); ++d) counts[d] += subtree.counts[d];
    if (!subtree.left) {
        parts.push_back({subtree.nodes, subtree.node_count, slot, next});
        return next + subtree.node_count - 1;
    }
    nodes[slot] = subtree.root;
    nodes[slot].first = next;
    const uint32_t after_left = place(*subtree.left, next, next + 2, nodes, parts, counts);
    return place(*subtree.right, next + 1, after_left, nodes, parts, counts);
}

/// Copies a depth-first part to its place: local index k > 0 lands at next + k - 1.
void copy_part(const Placement& part, NodeArray& nodes) {
    auto moved = [&](BvhNode node) {
        if (!node.is_leaf()) node.first = part.next + node.first - 1;
        return node;
    };
    nodes[part.slot] = moved(part.nodes[0]);
    for (uint32_t k = 1; k < part.count; ++k) nodes[part.next + k - 1] = moved(part.nodes[k]);
}

/// Counts the nodes of a subtree.
size_t node_count(const Subtree& subtree) {
    if (!subtree.left) return subtree.node_count;
    return 1 + node_count(*subtree.left) + node_count(*subtree.right);
}

/// Depths, leaf sizes and SAH cost of the finished tree, summed over its nodes in
/// depth-first order (parents before children, left subtree first), so the float sums
/// are the same however the tree was built.
class TreeStats {
public:
    TreeStats(const SahCostModel& model, uint32_t max_leaf_size) : model_(model), max_leaf_size_(max_leaf_size) {}

    void gather(const Bvh& bvh, BvhBuildStats& stats) {
        stats.nodes = uint32_t(bvh.nodes.size());
        // One leaf-order triangle per id (the build gathers this while they are copied).
        stats.memory_bytes = bvh.nodes.size() * sizeof(BvhNode) + bvh.prim_ids.size() * sizeof(uint32_t) +
                             bvh.prim_ids.size() * sizeof(Triangle);
        if (bvh.nodes.empty()) return;
        root_area_ = bvh.nodes[0].bounds.area();
        struct Visit {
            uint32_t node, depth;
        };
        std::vector<Visit> stack{{0, 0}};
        while (!stack.empty()) {
            const Visit v = stack.back();
            stack.pop_back();
            const BvhNode& node = bvh.nodes[v.node];
            add_node(node.bounds, v.depth, node.count, stats);
            if (!node.is_leaf()) {
                stack.push_back({node.first + 1, v.depth + 1});
                stack.push_back({node.first, v.depth + 1});
            }
        }
        if (stats.leaves == 0) return;
        stats.avg_leaf_depth = depth_sum_ / stats.leaves;
        stats.sah_cost = sah_;
    }

private:
    /// One node's share of the SAH cost (its hit probability times C_trav for an
    /// interior node, times count · C_isect for a leaf), and the leaf statistics.
    void add_node(const Aabb& bounds, uint32_t depth, uint32_t leaf_count, BvhBuildStats& stats) {
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
        sah_ += p * model_.tests(leaf_count) * model_.cost_isect;
    }

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

Expected<Bvh> build_bvh(const Mesh& mesh, const BvhConfig& requested, BuildRecorder* recorder,
                        WorkProgress* progress) {
    if (auto err = validate(requested)) return *err;
    const auto start = std::chrono::steady_clock::now();
    Bvh bvh;
    bvh.build_config = requested;
    bvh.build_config.width = 2;  // this is the binary tree; build_accelerator() collapses it when asked
    const BvhConfig& config = bvh.build_config;
    BvhBuildStats& stats = bvh.build_stats;
    const auto n = uint32_t(mesh.triangle_count());
    stats.triangles = n;
    start_stage(progress, n);
    auto gather_stats = [&] {
        TreeStats(config.sah_model(), uint32_t(config.max_leaf_size)).gather(bvh, stats);
    };

    if (n > 0) {
        PrimRefs refs = make_prefaulted<PrimRefs>(n);
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, kParallelChunk), [&](const tbb::blocked_range<uint32_t>& r) {
            for (uint32_t i = r.begin(); i < r.end(); ++i)
                refs[i] = make_prim_ref(mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2), i);
        });
        std::unique_ptr<Splitter> splitter = make_splitter(config, std::move(refs));

        // With a recorder the decisions must come in depth-first order: one task builds all.
        const Task root{0, 0, n, 0, false, {}, {}};
        std::unique_ptr<Subtree> tree;
        std::vector<BvhNode> depth_first;
        std::optional<NodeStore> store;
        if (recorder) {
            tree = std::make_unique<Subtree>();
            build_depth_first(*splitter, root, config, depth_first, tree->counts, recorder, progress);
            tree->nodes = depth_first.data();
            tree->node_count = uint32_t(depth_first.size());
        } else {
            store.emplace(n);
            tree = build_subtree(*splitter, root, config, *store, progress);
        }
        if (cancelled(progress)) return WorkProgress::cancelled_error();
        // Each big array is made only after the one before it is freed: the peak is
        // lower, and the new array gets the pages just given back (a fresh page costs
        // the kernel a zeroing, and on a virtual machine often the host a fault: at
        // 10M triangles making the node array while the build records were still held
        // took 0.7-0.8 s of a 3.2 s build; see docs/performance.md).
        // Leaf order: the triangles of each leaf next to each other, as the traversal reads them.
        bvh.prim_ids.resize(n);
        tbb::parallel_for(tbb::blocked_range<uint32_t>(0, n, kParallelChunk), [&](const tbb::blocked_range<uint32_t>& r) {
            for (uint32_t k = r.begin(); k < r.end(); ++k) bvh.prim_ids[k] = splitter->prim_id(k);
        });
        splitter.reset();  // the build records
        bvh.nodes.resize(node_count(*tree));
        std::vector<Placement> parts;
        place(*tree, 0, 1, bvh.nodes, parts, stats.decisions);
        tbb::parallel_for(size_t(0), parts.size(), [&](size_t k) { copy_part(parts[k], bvh.nodes); });
        store.reset();
        // The statistics read the nodes and the ids alone: gathered (one serial walk)
        // while the triangles are copied.
        tbb::parallel_invoke([&] { bvh.triangles = make_triangles(mesh, bvh.prim_ids); }, gather_stats);
    } else {
        gather_stats();
    }
    write_notes(config, stats);
    stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

namespace {

/// The box of node n's subtree, written into every node of it (post-order). The two
/// children of a node near the root are refitted as two tasks; a box is a min and a
/// max, so the result is the same in any order.
Aabb refit_subtree(Bvh& bvh, const Mesh& mesh, uint32_t n, uint32_t depth) {
    BvhNode& node = bvh.nodes[n];
    Aabb box;
    if (node.is_leaf()) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k) box.grow(mesh.triangle_bounds(bvh.prim_ids[k]));
    } else {
        constexpr uint32_t kTaskDepth = 8;  // 2^8 tasks: enough for two cores to balance
        Aabb left, right;
        if (depth < kTaskDepth) {
            tbb::parallel_invoke([&] { left = refit_subtree(bvh, mesh, node.first, depth + 1); },
                                 [&] { right = refit_subtree(bvh, mesh, node.first + 1, depth + 1); });
        } else {
            left = refit_subtree(bvh, mesh, node.first, depth + 1);
            right = refit_subtree(bvh, mesh, node.first + 1, depth + 1);
        }
        box = left;
        box.grow(right);
    }
    node.bounds = box;
    return box;
}

}  // namespace

std::optional<Error> refit_bvh(Bvh& bvh, const Mesh& mesh) {
    const auto start = std::chrono::steady_clock::now();
    if (mesh.triangle_count() != bvh.prim_ids.size())
        return Error{"a refit needs the mesh the BVH was built over, moved: the BVH has " +
                     std::to_string(bvh.prim_ids.size()) + " triangles, this mesh " +
                     std::to_string(mesh.triangle_count())};
    if (!bvh.nodes.empty()) refit_subtree(bvh, mesh, 0, 0);
    fill_triangles(mesh, bvh.prim_ids, bvh.triangles);
    if (bvh.triangle_test == TriangleTestKind::Watertight) bvh.corners = make_corners(mesh, bvh.prim_ids);
    bvh.build_stats.refit_ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return std::nullopt;
}

void gather_refit_stats(Bvh& bvh) {
    BvhBuildStats& stats = bvh.build_stats;
    stats.leaves = stats.max_depth = stats.leaves_over_limit = 0;
    stats.leaf_size_histogram.clear();
    stats.avg_leaf_depth = stats.sah_cost = 0;
    const BvhConfig& config = bvh.build_config;
    TreeStats(config.sah_model(), uint32_t(config.max_leaf_size)).gather(bvh, stats);
    const std::string refitted =
        "refitted to moved triangles: the decisions, the other notes and build_ms are the build's, over the "
        "earlier positions";
    if (std::find(stats.notes.begin(), stats.notes.end(), refitted) == stats.notes.end()) stats.notes.push_back(refitted);
}

}  // namespace accelviz
