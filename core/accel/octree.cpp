#include "core/accel/octree.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <span>
#include <sstream>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "core/geometry/morton_order.h"
#include "core/geometry/triangle_box.h"

namespace accelviz {

std::optional<Error> validate(const OctreeConfig& c) {
    if (c.max_depth < 1 || c.max_depth > kOctreeMaxDepth) return Error{"--octree-max-depth must be in 1.." + std::to_string(kOctreeMaxDepth)};
    if (c.leaf_size < 1) return Error{"--leaf-size must be at least 1"};
    if (!(c.max_duplication >= 1.0)) return Error{"octree max_duplication must be >= 1"};
    return std::nullopt;
}

namespace {

/// The octree's references under construction: the triangles' places in Morton order
/// (CornerTriples), 4 bytes each. A reference's box (SpatialRef) is not stored: under
/// the octree's rule (OctantSplit) it is the triangle's padded box cut down, level by
/// level, to each cell grown by 2·pad, and since each cell lies within its parent those
/// cuts come to one: the padded box ∩ the cell's box grown by 2·pad (box_in_cell), the
/// same floats. The lists copied from level to level are then a seventh of SpatialRefs'.
using OctreeRefs = std::vector<uint32_t, LargeArrayAllocator<uint32_t>>;
using OctantRefs = std::array<OctreeRefs, 8>;
/// Each triangle's box grown by pad (a root reference's box), by Morton place.
using RefBoxes = std::vector<Aabb, LargeArrayAllocator<Aabb>>;

struct WorkItem {
    uint32_t node;
    uint32_t depth;
    Aabb box;
    OctreeRefs refs;
    uint64_t progress_units;  ///< its part of PartitionProgress::kTotal
};

/// What building one subtree gives: local nodes (its root at 0), leaf references,
/// and the counts the stats add up.
struct Subtree {
    std::vector<OctreeNode> nodes;
    std::vector<uint32_t> prim_ids;
    SubtreeCounts counts;
};

/// What the octree's build reads of its triangles, by Morton place.
struct OctreeInput {
    const CornerTriples& triangles;  ///< the corners, for the straddlers' tests
    const RefBoxes& boxes;           ///< each triangle's box grown by pad
    float pad;

    /// Reference `tri`'s box in the cell `split` cuts (see OctreeRefs).
    Aabb box_in_cell(uint32_t tri, const OctantSplit& split) const { return intersection(boxes[tri], split.limit()); }
};

/// The references of the cell `box` split among its octants (cut at its centre,
/// OctantSplit): each appended to the list of every octant it reaches, in the cell's
/// order (big cells in parallel chunks: split_in_order).
void split_references(std::span<const uint32_t> refs, const Aabb& box, const OctreeInput& in, ClipMode clip,
                      const PartitionProgress& progress, OctantRefs& children) {
    const OctantSplit split(box, in.pad, clip);
    const Vec3 centre = split.centre();
    split_in_order(refs.size(), children, progress, [&](size_t begin, size_t end, OctantRefs& to) {
        for (size_t i = begin; i < end; ++i) {
            const uint32_t tri = refs[i];
            const Aabb ref_box = in.box_in_cell(tri, split);
            // Most references lie on one side of all three planes: their octant takes
            // them as they are (their box lies within it grown by 2·pad, so box_in_cell
            // there gives the same box).
            int octant = 0;
            bool straddles = false;
            for (int a = 0; a < 3; ++a) {
                const bool above = ref_box.hi[a] > centre[a];
                straddles |= above && ref_box.lo[a] < centre[a];
                octant |= int(above) << a;
            }
            if (!straddles) {
                to[size_t(octant)].push_back(tri);
                continue;
            }
            for (uint32_t m = split.reached(ref_box, in.triangles[tri]); m; m &= m - 1)
                to[size_t(__builtin_ctz(m))].push_back(tri);
        }
    });
}

/// Builds one subtree depth first, octant 0 first. A cell's octants' references are
/// split into the eight lists kept for its depth, and each octant is built from its
/// list in place: the lists of its ancestors' depths are the only others in use
/// meanwhile, so no cell allocates a list of its own once the lists have grown (a cell
/// handed on to be built separately gets a copy). A list of more than kKeepRefs
/// references is freed once its cell has split: where most triangles stay in one
/// octant for several levels, kept lists would hold the scene's references once per level.
class SubtreeBuilder {
public:
    /// Cells whose reference count is below `defer_below` (other than the root) are left
    /// as placeholders and handed to `deferred` (their node index is local), so that they
    /// can be built separately and spliced in (nullptr: none). `budget`: the most
    /// references this subtree may hold.
    SubtreeBuilder(const OctreeInput& in, const OctreeConfig& config, double budget, size_t defer_below,
                   std::vector<WorkItem>* deferred, PartitionProgress& progress)
        : in_(in), config_(config), budget_(budget), defer_below_(defer_below),
          deferred_(deferred), progress_(progress), lists_(size_t(config.max_depth) + 1) {}

    /// The subtree of `root`; unfinished if the progress was cancelled (the caller drops it).
    Subtree build(WorkItem root) {
        live_refs_ = root.refs.size();
        out_.nodes.emplace_back();
        build_cell(0, root.depth, root.box, root.refs, root.progress_units, true);
        return std::move(out_);
    }

private:
    static constexpr size_t kKeepRefs = size_t(1) << 18;

    void build_cell(uint32_t node, uint32_t depth, const Aabb& box, OctreeRefs& refs, uint64_t units, bool is_root) {
        if (progress_.cancelled()) return;
        const size_t n = refs.size();
        if (deferred_ && !is_root && n < defer_below_) {
            units = progress_.count_part(units, kTopParts);
            deferred_->push_back({node, depth, box, OctreeRefs(refs.begin(), refs.end()), units});
            return;
        }
        const Vec3 centre = box.center();
        bool split = n > size_t(config_.leaf_size) && int(depth) < config_.max_depth;
        for (int a = 0; a < 3 && split; ++a)
            if (!(centre[a] > box.lo[a] && centre[a] < box.hi[a])) split = false;  // cell too thin to cut
        OctantRefs* children = split ? &lists_[depth] : nullptr;
        if (split) {
            for (auto& c : *children) c.clear();
            split_references(refs, box, in_, config_.clip, progress_, *children);
            if (progress_.cancelled()) return;  // the lists may be short: dropped, as the whole tree
            // No progress: the triangles all reach every non-empty octant (two or more),
            // so cutting only copies them. (All of them in one octant is progress:
            // the cell shrinks around them.)
            size_t total = 0, non_empty = 0;
            bool all_full = true;
            for (const auto& c : *children) {
                total += c.size();
                if (!c.empty()) ++non_empty;
                if (!c.empty() && c.size() < n) all_full = false;
            }
            if (all_full && non_empty >= 2) {
                split = false;
                ++out_.counts.no_progress;
            } else if (double(live_refs_) + double(total) - double(n) > budget_) {
                split = false;
                out_.counts.budget_hit = true;
            } else {
                live_refs_ = uint64_t(int64_t(live_refs_) + int64_t(total) - int64_t(n));
                if (is_root || refs.capacity() > kKeepRefs) OctreeRefs().swap(refs);  // split: not read again
            }
        }
        if (!split) {
            out_.nodes[node] = OctreeNode{centre, uint32_t(out_.prim_ids.size()), uint32_t(n), true};
            out_.prim_ids.insert(out_.prim_ids.end(), refs.begin(), refs.end());
            out_.counts.add_leaf(n, depth, config_.max_depth, config_.leaf_size);
            progress_.leaf_done(units);
            return;
        }
        const uint32_t first = uint32_t(out_.nodes.size());
        out_.nodes[node] = OctreeNode{centre, first, 0, false};
        out_.nodes.resize(out_.nodes.size() + 8);
        // Each octant gets its share of the progress units; octant 7 what the others leave.
        size_t all_refs = 0;
        for (const auto& c : *children) all_refs += c.size();
        uint64_t units_left = units;
        for (int o = 0; o < 8; ++o) {
            OctreeRefs& part = (*children)[size_t(o)];
            const uint64_t share = o == 7 ? units_left : PartitionProgress::share_of(units, part.size(), all_refs);
            units_left -= share;
            build_cell(first + uint32_t(o), depth + 1, octant_box(box, centre, o), part, share, false);
            if (progress_.cancelled()) return;
        }
    }

    const OctreeInput& in_;
    const OctreeConfig& config_;
    double budget_;
    size_t defer_below_;
    std::vector<WorkItem>* deferred_;
    PartitionProgress& progress_;
    std::vector<OctantRefs> lists_;  ///< by depth: the octants' lists of the cell being built there
    uint64_t live_refs_ = 0;         ///< references in leaves + in cells not yet built
    Subtree out_;
};

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
    // The references name the triangles by their place in Morton order, whose corners
    // they read side by side (a cell's straddlers then lie near each other in memory,
    // whatever the file's order); the leaves get the mesh's ids back at the end.
    std::vector<uint32_t> order = morton_order(mesh, tree.bounds);
    CornerTriples triangles = corner_triples(mesh, order);
    RefBoxes boxes = make_prefaulted<RefBoxes>(triangles.size());
    OctreeRefs root_refs = make_prefaulted<OctreeRefs>(triangles.size());
    tbb::parallel_for(tbb::blocked_range<size_t>(0, triangles.size(), kRefsToShareOut),
                      [&](const tbb::blocked_range<size_t>& r) {
                          for (size_t k = r.begin(); k < r.end(); ++k) {
                              const auto& p = triangles[k];
                              boxes[k] = padded(triangle_box(p[0], p[1], p[2]), pad);
                              root_refs[k] = uint32_t(k);
                          }
                      });
    const OctreeInput input{triangles, boxes, pad};
    const Subtree top = SubtreeBuilder(input, config, budget, defer_below, &deferred, top_progress)
                            .build({0, 0, tree.bounds, std::move(root_refs), PartitionProgress::kTotal});
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
            subtrees[which[i]] =
                SubtreeBuilder(input, config, std::max(share, 1.0), 0, nullptr, progress).build(item);
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
    // What the splits read, freed before the tree's arrays are made (the splice and the
    // triangle copy), which would otherwise come on top of them.
    std::vector<WorkItem>().swap(deferred);
    CornerTriples().swap(triangles);
    RefBoxes().swap(boxes);
    tree.splice_all(placeholders, subtrees);
    for (const Subtree& sub : subtrees) {
        counts.add(sub.counts);
    }
    std::vector<Subtree>().swap(subtrees);

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
                   start, shared_progress, std::move(order));
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
