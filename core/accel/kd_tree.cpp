#include "core/accel/kd_tree.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <sstream>

#include <tbb/parallel_for.h>

#include "core/accel/kd_sah.h"
#include "core/accel/kd_sorted_bounds.h"
#include "core/geometry/triangle_box.h"

namespace accelviz {

std::string_view to_string(KdBuilder builder) { return builder == KdBuilder::Median ? "median" : "sah"; }

std::optional<KdBuilder> parse_kd_builder(std::string_view name) {
    if (name == "median") return KdBuilder::Median;
    if (name == "sah") return KdBuilder::Sah;
    return std::nullopt;
}

const std::vector<std::string>& kd_builder_names() {
    static const std::vector<std::string> names = {"median", "sah"};
    return names;
}

std::optional<Error> validate(const KdConfig& c) {
    if (c.max_depth < 0 || c.max_depth > kKdMaxDepth)
        return Error{"--kd-max-depth must be in 0.." + std::to_string(kKdMaxDepth) + " (0 = automatic, 8 + 1.3·log2(N))"};
    if (c.leaf_size < 1) return Error{"--leaf-size must be at least 1"};
    if (!(c.cost_trav >= 0.0f) || !std::isfinite(c.cost_trav)) return Error{"--cost-trav must be >= 0"};
    if (!(c.cost_isect > 0.0f) || !std::isfinite(c.cost_isect)) return Error{"--cost-isect must be > 0"};
    if (!(c.empty_bonus >= 0.0f && c.empty_bonus < 1.0f)) return Error{"--kd-empty-bonus must be in [0, 1)"};
    if (!(c.max_duplication >= 1.0)) return Error{"KD max_duplication must be >= 1"};
    if (c.leaf_lanes != 1 && c.leaf_lanes != 4) return Error{"KD leaf lanes must be 1 or 4"};
    return std::nullopt;
}

int kd_max_depth(const KdConfig& config, size_t triangles) {
    if (config.max_depth > 0) return config.max_depth;
    const double automatic = 8.0 + 1.3 * std::log2(double(std::max<size_t>(triangles, 1)));
    return std::clamp(int(std::lround(automatic)), 1, kKdMaxDepth);
}

namespace {

/// The cheapest plane of the SAH sweep (kd_sah.h) over the node's sorted bounds, found
/// by counting in small nodes (which need no lists); axis -1 when no plane lies
/// strictly inside the node. The first cheapest in the sweep's order (axis, then
/// position); big nodes sweep their three axes in parallel.
KdPlane best_sah_plane(const SpatialRefs& refs, const SortedBounds& bounds, const Aabb& box, const KdConfig& c,
                       const PartitionProgress& progress) {
    if (refs.size() <= kKdCountingMax) return kd_cheapest_plane_by_counting(refs, box, c);
    std::array<KdPlane, 3> per_axis;
    const auto sweep_axis = [&](int a) {
        KdPlane& axis_best = per_axis[size_t(a)];
        sweep_sorted_kd_sah_axis<true>(
            bounds.list(2 * a), bounds.list(2 * a + 1), box, c, a,
            [&](int, float s, size_t, size_t, double cost) {
                if (cost < axis_best.cost) axis_best = {a, s, cost};
            },
            [&] { return progress.cancelled(); });
    };
    for_each_part(refs.size(), 3, sweep_axis);
    KdPlane best;
    for (const KdPlane& p : per_axis)
        if (p.cost < best.cost) best = p;
    return best;
}

/// The references of the node `box` split at s on axis a (split_reference): those
/// reaching the lower child appended to `below`, those reaching the upper one to `above`,
/// in the node's order (big nodes in parallel chunks: split_in_order).
void split_references(const SpatialRefs& refs, int a, float s, const Aabb& box, const CornerTriples& triangles,
                      float pad, ClipMode clip, const PartitionProgress& progress, SpatialRefs& below,
                      SpatialRefs& above) {
    std::array<SpatialRefs, 2> sides = {std::move(below), std::move(above)};
    sides[0].reserve(refs.size());
    sides[1].reserve(refs.size());
    split_in_order(refs.size(), sides, progress, [&](size_t begin, size_t end, std::array<SpatialRefs, 2>& to) {
        Vec3 planes;
        planes[a] = s;
        ChildRefs parts;
        for (size_t i = begin; i < end; ++i) {
            split_reference(refs[i], triangles, box, planes, 1u << a, pad, part_rule(clip), parts);
            for (int k = 0; k < parts.count; ++k) to[parts.child[k] == 0 ? 0 : 1].push_back(parts.ref[k]);
        }
    });
    below = std::move(sides[0]);
    above = std::move(sides[1]);
}

struct WorkItem {
    uint32_t node;
    uint32_t depth;
    Aabb box;
    SpatialRefs refs;
    uint64_t progress_units;  ///< its part of PartitionProgress::kTotal
    SortedBounds bounds = {};  ///< made for a node the SAH will sweep (not for leaves-to-be, counting or deferred ones)
};

/// What building one subtree gives: local nodes (its root at 0), leaf references,
/// and the counts the stats add up.
struct Subtree {
    std::vector<KdNode> nodes;
    std::vector<uint32_t> prim_ids;
    SubtreeCounts counts;
    double sah_cost = 0;
};

/// The fixed inputs of every node's decision.
struct BuildContext {
    const CornerTriples& triangles;
    const KdConfig& config;
    float pad;
    double root_area;
    int depth_limit;
};

/// Builds the subtree of `root` depth first over an explicit work stack. Nodes
/// whose reference count is below `defer_below` (other than the root) are left
/// as placeholders and handed to `deferred` (their node index is local), so that
/// they can be built separately and spliced in. `budget`: the most references
/// this subtree may hold.
Subtree build_subtree(const BuildContext& ctx, WorkItem root, double budget, size_t defer_below,
                      std::vector<WorkItem>* deferred, PartitionProgress& progress) {
    const KdConfig& config = ctx.config;
    Subtree out;
    uint64_t live_refs = root.refs.size();  // references in leaves + in pending work
    std::vector<WorkItem> work;
    root.node = 0;
    out.nodes.emplace_back();
    work.push_back(std::move(root));
    SpatialRefs below, above;
    // Whether a node of `count` references at `depth` sweeps sorted bounds if this
    // subtree builds it (it may split, and has too many references to count), and
    // whether it will here (a node handed on as a subtree sorts its own).
    const auto sweeps_sorted = [&](size_t count, uint32_t depth) {
        return config.builder == KdBuilder::Sah && count > kKdCountingMax && count > size_t(config.leaf_size) &&
               int(depth) < ctx.depth_limit;
    };
    const auto will_sweep = [&](size_t count, uint32_t depth) {
        return sweeps_sorted(count, depth) && !(deferred && count < defer_below);
    };
    bool is_root = true;
    while (!work.empty()) {
        if (progress.cancelled()) return out;  // the caller drops the unfinished tree
        WorkItem item = std::move(work.back());
        work.pop_back();
        const size_t n = item.refs.size();
        if (deferred && !is_root && n < defer_below) {
            item.progress_units = progress.count_part(item.progress_units, kTopParts);
            deferred->push_back(std::move(item));
            continue;
        }
        is_root = false;
        const double p = kd_area(item.box) / ctx.root_area;  // hit probability, for the tree's SAH cost

        // Choose a plane, or decide on a leaf.
        KdPlane plane;
        bool split = n > size_t(config.leaf_size) && int(item.depth) < ctx.depth_limit;
        if (split && config.builder == KdBuilder::Sah) {
            if (sweeps_sorted(n, item.depth) && !item.bounds.made()) {
                item.bounds = sort_bounds(item.refs);
                if (progress.cancelled()) return out;  // a big root's sorts take a good part of a second
            }
            plane = best_sah_plane(item.refs, item.bounds, item.box, config, progress);
            split = plane.axis >= 0 && plane.cost < config.cost_isect * kd_tests(config, n);
        }
        below.clear();
        above.clear();
        if (split) {
            // Median: longest axis first, then the others in turn until one separates something.
            const Vec3 e = item.box.extent();
            const int longest = max_axis(e);
            for (int attempt = 0; attempt < 3; ++attempt) {
                const int a = config.builder == KdBuilder::Sah ? plane.axis : (longest + attempt) % 3;
                const float s = config.builder == KdBuilder::Sah ? plane.position : item.box.center()[a];
                below.clear();
                above.clear();
                split_references(item.refs, a, s, item.box, ctx.triangles, ctx.pad, config.clip, progress, below, above);
                plane.axis = a;
                plane.position = s;
                const bool separates = (below.size() < n || above.size() < n) && s > item.box.lo[a] && s < item.box.hi[a];
                if (separates || config.builder == KdBuilder::Sah) {
                    split = separates;
                    break;
                }
                split = false;
            }
            if (!split) ++out.counts.no_progress;
            if (progress.cancelled()) return out;  // the lists may be short: dropped, as the whole tree
        }
        if (split && double(live_refs) + double(below.size() + above.size()) - double(n) > budget) {
            split = false;
            out.counts.budget_hit = true;
        }

        if (!split) {
            KdNode& leaf = out.nodes[item.node];
            leaf = KdNode::leaf(uint32_t(out.prim_ids.size()), uint32_t(n));
            for (const SpatialRef& r : item.refs) out.prim_ids.push_back(r.tri);
            out.counts.add_leaf(n, item.depth, ctx.depth_limit, config.leaf_size);
            out.sah_cost += p * kd_tests(config, n) * config.cost_isect;
            progress.leaf_done(item.progress_units);
            continue;
        }
        live_refs = uint64_t(int64_t(live_refs) + int64_t(below.size() + above.size()) - int64_t(n));
        const uint32_t first = uint32_t(out.nodes.size());
        out.nodes[item.node] = KdNode::interior(plane.axis, plane.position, first);
        out.nodes.emplace_back();
        out.nodes.emplace_back();
        out.sah_cost += p * config.cost_trav;
        Aabb lower = item.box, upper = item.box;
        lower.hi[plane.axis] = plane.position;
        upper.lo[plane.axis] = plane.position;
        const uint64_t below_units =
            PartitionProgress::share_of(item.progress_units, below.size(), below.size() + above.size());
        auto [below_bounds, above_bounds] =
            children_bounds(item.refs, item.bounds, {&below, &above},
                            {will_sweep(below.size(), item.depth + 1), will_sweep(above.size(), item.depth + 1)});
        item.bounds = {};
        // Upper pushed first so the lower child is built first: depth-first order.
        work.push_back({first + 1, item.depth + 1, upper, std::move(above), item.progress_units - below_units,
                        std::move(above_bounds)});
        work.push_back({first, item.depth + 1, lower, std::move(below), below_units, std::move(below_bounds)});
        above = {};
        below = {};
        item.refs = {};
    }
    return out;
}


}  // namespace

Expected<KdTree> build_kd_tree(const Mesh& mesh, const KdConfig& config, WorkProgress* shared_progress) {
    const auto start = std::chrono::steady_clock::now();
    if (auto err = validate(config)) return *err;
    KdTree tree;
    KdBuildStats& st = tree.build_stats;
    const int depth_limit = kd_max_depth(config, uint32_t(mesh.triangle_count()));
    st.depth_limit = uint32_t(depth_limit);
    const float pad = tree.begin_build(mesh, config, start);
    if (st.triangles == 0) return tree;
    const CornerTriples triangles = corner_triples(mesh);
    const BuildContext ctx{triangles, config, pad, kd_area(tree.bounds), depth_limit};
    const double budget = config.max_duplication * st.triangles;
    SubtreeCounts counts;  // the whole tree's: the top's and every subtree's

    // The top of the tree first, one node at a time; subtrees under nodes with fewer
    // than N/64 references are collected, built in parallel (each on its own, so the
    // result does not depend on the threads), and spliced in in depth-first order.
    // The reference budget is shared out in proportion to their sizes.
    std::vector<WorkItem> deferred;
    const size_t defer_below = std::max<size_t>(4096, st.triangles / 64);
    start_stage(shared_progress, PartitionProgress::kTotal);
    PartitionProgress top_progress(shared_progress);
    const Subtree top =
        build_subtree(ctx, WorkItem{0, 0, tree.bounds, root_references(mesh, pad), PartitionProgress::kTotal},
                      budget, defer_below, &deferred, top_progress);
    top_progress.flush();
    tree.nodes.assign(top.nodes.begin(), top.nodes.end());
    tree.prim_ids.assign(top.prim_ids.begin(), top.prim_ids.end());
    counts.add(top.counts);
    st.sah_cost += top.sah_cost;
    double deferred_refs = 0;
    for (const WorkItem& w : deferred) deferred_refs += double(w.refs.size());
    const double budget_left = std::max(0.0, budget - double(top.prim_ids.size()));
    std::vector<uint32_t> placeholders;
    for (const WorkItem& w : deferred) placeholders.push_back(w.node);
    std::vector<Subtree> subtrees(deferred.size());
    tbb::parallel_for(size_t(0), deferred.size(), [&](size_t k) {
        const double share = budget_left * double(deferred[k].refs.size()) / std::max(deferred_refs, 1.0);
        PartitionProgress progress(shared_progress);
        subtrees[k] = build_subtree(ctx, std::move(deferred[k]), std::max(share, 1.0), 0, nullptr, progress);
    });
    if (cancelled(shared_progress)) return WorkProgress::cancelled_error();
    size_t node_count = tree.nodes.size();
    for (const Subtree& sub : subtrees) node_count += sub.nodes.empty() ? 0 : sub.nodes.size() - 1;
    if (node_count > KdNode::kMaxIndex)
        return Error{"the KD tree would have " + std::to_string(node_count) + " nodes, more than its nodes can index (" +
                     std::to_string(KdNode::kMaxIndex) + "): raise --leaf-size or lower --kd-max-depth"};
    tree.splice_all(placeholders, subtrees);
    for (const Subtree& sub : subtrees) {
        counts.add(sub.counts);
        st.sah_cost += sub.sah_cost;
    }

    counts.write_to(st);
    tree.end_build(mesh,
                   {.parts = "nodes",
                    .leaves_at_depth_limit = st.leaves_at_depth_limit,
                    .depth_limit = depth_limit,
                    .leaf_size = config.leaf_size,
                    .not_split = config.builder == KdBuilder::Median ? counts.no_progress : 0,
                    .not_split_why = "no axis' middle plane separates their triangles",
                    .budget_hit = counts.budget_hit,
                    .max_duplication = config.max_duplication},
                   start, shared_progress);
    return tree;
}

nlohmann::json KdTree::config() const {
    const KdConfig& c = build_config;
    return {{"builder", std::string(to_string(c.builder))},
            {"max_depth", c.max_depth},
            {"leaf_size", c.leaf_size},
            {"cost_trav", c.cost_trav},
            {"cost_isect", c.cost_isect},
            {"empty_bonus", c.empty_bonus},
            {"clip", std::string(to_string(c.clip))},
            {"strict_cell", c.strict_cell},
            {"mailbox", c.mailbox},
            {"leaf_lanes", c.leaf_lanes},
            {"triangle_test", std::string(to_string(triangle_test))}};
}

nlohmann::json KdTree::stats() const {
    nlohmann::json out = partition_stats_json(build_stats);
    out["depth_limit"] = build_stats.depth_limit;
    out["sah_cost"] = build_stats.sah_cost;
    return out;
}

std::vector<Aabb> KdTree::node_boxes() const {
    std::vector<Aabb> boxes(nodes.size());
    if (!nodes.empty()) boxes[0] = bounds;
    // Children follow their parent in the flat array (first > parent), so one pass fills them.
    for (size_t i = 0; i < nodes.size(); ++i) {
        const KdNode& n = nodes[i];
        if (n.is_leaf()) continue;
        Aabb lower = boxes[i], upper = boxes[i];
        lower.hi[n.axis()] = n.split();
        upper.lo[n.axis()] = n.split();
        boxes[n.lower_child()] = lower;
        boxes[n.upper_child()] = upper;
    }
    return boxes;
}

}  // namespace accelviz
