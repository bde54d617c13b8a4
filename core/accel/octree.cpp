#include "core/accel/octree.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <sstream>

#include <tbb/parallel_for.h>

#include "core/geometry/triangle_box.h"

namespace accelviz {

std::optional<Error> validate(const OctreeConfig& c) {
    if (c.max_depth < 1 || c.max_depth > kOctreeMaxDepth) return Error{"--octree-max-depth must be in 1.." + std::to_string(kOctreeMaxDepth)};
    if (c.leaf_size < 1) return Error{"--leaf-size must be at least 1"};
    if (!(c.max_duplication >= 1.0)) return Error{"octree max_duplication must be >= 1"};
    return std::nullopt;
}

namespace {

struct WorkItem {
    uint32_t node;
    uint32_t depth;
    Aabb box;
    SpatialRefs refs;
    uint64_t progress_units;  ///< its part of PartitionProgress::kTotal
};

/// What building one subtree gives: local nodes (its root at 0), leaf references,
/// and the counts the stats add up.
struct Subtree {
    std::vector<OctreeNode> nodes;
    std::vector<uint32_t> prim_ids;
    SubtreeCounts counts;
};

using OctantRefs = std::array<SpatialRefs, 8>;

/// The references of a cell split among its octants (cut at `centre`, split_reference):
/// each appended to the list of every octant it reaches, in the cell's order (big
/// cells in parallel chunks: split_in_order).
void split_references(const SpatialRefs& refs, const Aabb& box, Vec3 centre, const Mesh& mesh, float pad,
                      ClipMode clip, const PartitionProgress& progress, OctantRefs& children) {
    split_in_order(refs.size(), children, progress, [&](size_t begin, size_t end, OctantRefs& to) {
        ChildRefs parts;
        for (size_t i = begin; i < end; ++i) {
            split_reference(refs[i], mesh, box, centre, 7u, pad, clip, parts);
            for (int k = 0; k < parts.count; ++k) to[parts.child[k]].push_back(parts.ref[k]);
        }
    });
}

/// Builds the subtree of `root` depth first over an explicit work stack. Cells whose
/// reference count is below `defer_below` (other than the root) are left as
/// placeholders and handed to `deferred` (their node index is local), so that they
/// can be built separately and spliced in. `budget`: the most references this
/// subtree may hold.
Subtree build_subtree(const Mesh& mesh, const OctreeConfig& config, float pad, WorkItem root, double budget,
                      size_t defer_below, std::vector<WorkItem>* deferred, PartitionProgress& progress) {
    Subtree out;
    uint64_t live_refs = root.refs.size();  // references in leaves + in pending work
    std::vector<WorkItem> work;
    root.node = 0;
    out.nodes.emplace_back();
    work.push_back(std::move(root));
    OctantRefs children;
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
        const Vec3 centre = item.box.center();
        bool split = n > size_t(config.leaf_size) && int(item.depth) < config.max_depth;
        for (int a = 0; a < 3 && split; ++a)
            if (!(centre[a] > item.box.lo[a] && centre[a] < item.box.hi[a])) split = false;  // cell too thin to cut
        if (split) {
            for (auto& c : children) c.clear();
            split_references(item.refs, item.box, centre, mesh, pad, config.clip, progress, children);
            if (progress.cancelled()) return out;  // the lists may be short: dropped, as the whole tree
            // No progress: the triangles all reach every non-empty octant (two or more),
            // so cutting only copies them. (All of them in one octant is progress:
            // the cell shrinks around them.)
            size_t total = 0, non_empty = 0;
            bool all_full = true;
            for (const auto& c : children) {
                total += c.size();
                if (!c.empty()) ++non_empty;
                if (!c.empty() && c.size() < n) all_full = false;
            }
            if (all_full && non_empty >= 2) {
                split = false;
                ++out.counts.no_progress;
            } else if (double(live_refs) + double(total) - double(n) > budget) {
                split = false;
                out.counts.budget_hit = true;
            } else {
                live_refs = uint64_t(int64_t(live_refs) + int64_t(total) - int64_t(n));
            }
        }
        if (!split) {
            OctreeNode& leaf = out.nodes[item.node];
            leaf = OctreeNode{centre, uint32_t(out.prim_ids.size()), uint32_t(n), true};
            for (const SpatialRef& r : item.refs) out.prim_ids.push_back(r.tri);
            out.counts.add_leaf(n, item.depth, config.max_depth, config.leaf_size);
            progress.leaf_done(item.progress_units);
            continue;
        }
        const uint32_t first = uint32_t(out.nodes.size());
        out.nodes[item.node] = OctreeNode{centre, first, 0, false};
        out.nodes.resize(out.nodes.size() + 8);
        // Octant 7 pushed first, so octant 0 is built first: depth-first order. Each
        // octant's references are copied out at their size: the eight scratch lists
        // keep their capacity for the next cell. Octant 7 gets the progress units
        // the others leave.
        size_t all_refs = 0;
        for (const auto& c : children) all_refs += c.size();
        uint64_t units_left = item.progress_units;
        for (int o = 7; o >= 0; --o) {
            const SpatialRefs& refs = children[size_t(o)];
            const uint64_t units = o == 7 ? 0 : PartitionProgress::share_of(item.progress_units, refs.size(), all_refs);
            units_left -= units;
            work.push_back({first + uint32_t(o), item.depth + 1, octant_box(item.box, centre, o),
                            SpatialRefs(refs.begin(), refs.end()), units});
        }
        work[work.size() - 8].progress_units = units_left;
        item.refs = {};
    }
    return out;
}


}  // namespace

Expected<Octree> build_octree(const Mesh& mesh, const OctreeConfig& config, WorkProgress* shared_progress) {
    const auto start = std::chrono::steady_clock::now();
    if (auto err = validate(config)) return *err;
    Octree tree;
    OctreeBuildStats& st = tree.build_stats;
    const float pad = tree.begin_build(mesh, config, start);
    if (st.triangles == 0) return tree;
    const double budget = config.max_duplication * st.triangles;
    SubtreeCounts counts;  // the whole tree's: the top's and every subtree's

    // As the KD tree: the top of the tree first, one cell at a time; subtrees under
    // cells with fewer than N/64 references are collected, built in parallel (each on
    // its own, so the result does not depend on the threads), and spliced in in
    // depth-first order. The reference budget is shared out in proportion to their
    // sizes; subtrees that ran out of their share are built again with what the
    // others left unused, shared out the same way, so that a budget the whole tree
    // stays within does not stop one part of it.
    std::vector<WorkItem> deferred;
    const size_t defer_below = std::max<size_t>(4096, st.triangles / 64);
    start_stage(shared_progress, PartitionProgress::kTotal);
    PartitionProgress top_progress(shared_progress);
    const Subtree top = build_subtree(mesh, config, pad,
                                      WorkItem{0, 0, tree.bounds, root_references(mesh, pad), PartitionProgress::kTotal},
                                      budget, defer_below, &deferred, top_progress);
    top_progress.flush();
    tree.nodes.assign(top.nodes.begin(), top.nodes.end());
    tree.prim_ids.assign(top.prim_ids.begin(), top.prim_ids.end());
    counts.add(top.counts);
    std::vector<uint32_t> placeholders;
    for (const WorkItem& w : deferred) placeholders.push_back(w.node);
    std::vector<Subtree> subtrees(deferred.size());
    auto build_shares = [&](const std::vector<size_t>& which, double budget_left) {
        double refs = 0;
        for (size_t k : which) refs += double(deferred[k].refs.size());
        tbb::parallel_for(size_t(0), which.size(), [&](size_t i) {
            const WorkItem& item = deferred[which[i]];
            const double share = budget_left * double(item.refs.size()) / std::max(refs, 1.0);
            PartitionProgress progress(shared_progress);
            subtrees[which[i]] = build_subtree(mesh, config, pad, item, std::max(share, 1.0), 0, nullptr, progress);
        });
    };
    std::vector<size_t> all(deferred.size());
    for (size_t k = 0; k < all.size(); ++k) all[k] = k;
    build_shares(all, std::max(0.0, budget - double(top.prim_ids.size())));
    std::vector<size_t> again;
    double used = double(top.prim_ids.size());
    uint64_t again_units = 0;
    for (size_t k = 0; k < subtrees.size(); ++k) {
        if (subtrees[k].counts.budget_hit) {
            again.push_back(k);
            again_units += deferred[k].progress_units;
        } else {
            used += double(subtrees[k].prim_ids.size());
        }
    }
    if (!again.empty() && !cancelled(shared_progress)) {
        // A stage of its own, so that the bar does not wait at the end meanwhile (at
        // 10M triangles this is seconds): each subtree counts its units again.
        start_stage(shared_progress, again_units, "again, the parts over their share of the reference budget");
        build_shares(again, std::max(0.0, budget - used));
    }
    if (cancelled(shared_progress)) return WorkProgress::cancelled_error();
    tree.splice_all(placeholders, subtrees);
    for (const Subtree& sub : subtrees) {
        counts.add(sub.counts);
    }

    counts.write_to(st);
    tree.end_build(mesh,
                   {.parts = "cells",
                    .leaves_at_depth_limit = st.leaves_at_depth_limit,
                    .depth_limit = config.max_depth,
                    .leaf_size = config.leaf_size,
                    .not_split = counts.no_progress,
                    .not_split_why = "every non-empty octant would hold all of their triangles",
                    .budget_hit = counts.budget_hit,
                    .max_duplication = config.max_duplication},
                   start, shared_progress);
    return tree;
}

nlohmann::json Octree::config() const {
    const OctreeConfig& c = build_config;
    return {{"max_depth", c.max_depth},
            {"leaf_size", c.leaf_size},
            {"clip", std::string(to_string(c.clip))},
            {"mailbox", c.mailbox},
            {"triangle_test", std::string(to_string(triangle_test))}};
}

nlohmann::json Octree::stats() const { return partition_stats_json(build_stats); }

std::vector<Aabb> Octree::node_boxes() const {
    std::vector<Aabb> boxes(nodes.size());
    if (!nodes.empty()) boxes[0] = bounds;
    // Children follow their parent in the flat array (first > parent), so one pass fills them.
    for (size_t i = 0; i < nodes.size(); ++i) {
        const OctreeNode& n = nodes[i];
        if (n.is_leaf()) continue;
        for (int o = 0; o < 8; ++o) boxes[n.first + uint32_t(o)] = octant_box(boxes[i], n.centre, o);
    }
    return boxes;
}

}  // namespace accelviz
