#include "core/accel/octree.h"

#include <algorithm>
#include <chrono>
#include <sstream>

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
    std::vector<SpatialRef> refs;
};
}  // namespace

Expected<Octree> build_octree(const Mesh& mesh, const OctreeConfig& config) {
    const auto start = std::chrono::steady_clock::now();
    if (auto err = validate(config)) return *err;
    Octree tree;
    OctreeBuildStats& st = tree.build_stats;
    const float pad = tree.begin_build(mesh, config, start);
    if (st.triangles == 0) return tree;
    const double budget = config.max_duplication * st.triangles;
    uint64_t live_refs = st.triangles;
    bool budget_hit = false;
    uint32_t no_progress = 0;

    std::vector<WorkItem> work;
    work.push_back({0, 0, tree.bounds, root_references(mesh, pad)});
    tree.nodes.emplace_back();
    std::array<std::vector<SpatialRef>, 8> children;
    while (!work.empty()) {
        WorkItem item = std::move(work.back());
        work.pop_back();
        const size_t n = item.refs.size();
        const Vec3 centre = item.box.center();
        bool split = n > size_t(config.leaf_size) && int(item.depth) < config.max_depth;
        for (int a = 0; a < 3 && split; ++a)
            if (!(centre[a] > item.box.lo[a] && centre[a] < item.box.hi[a])) split = false;  // cell too thin to cut
        if (split) {
            for (auto& c : children) c.clear();
            for (const SpatialRef& r : item.refs) {
                // The octants the reference's box reaches (below iff lo < c, above iff hi > c; see SpatialRef).
                int lo_side[3], hi_side[3];
                for (int a = 0; a < 3; ++a) {
                    const bool above = r.box.hi[a] > centre[a];
                    const bool below = r.box.lo[a] < centre[a] || !above;
                    lo_side[a] = below ? 0 : 1;
                    hi_side[a] = above ? 1 : 0;
                }
                for (int z = lo_side[2]; z <= hi_side[2]; ++z)
                    for (int y = lo_side[1]; y <= hi_side[1]; ++y)
                        for (int x = lo_side[0]; x <= hi_side[0]; ++x) {
                            const int o = x | y << 1 | z << 2;
                            if (auto c = clip_reference(r, mesh, octant_box(item.box, centre, o), pad, config.clip))
                                children[size_t(o)].push_back(*c);
                        }
            }
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
                ++no_progress;
            } else if (double(live_refs) + double(total) - double(n) > budget) {
                split = false;
                budget_hit = true;
            } else {
                live_refs = uint64_t(int64_t(live_refs) + int64_t(total) - int64_t(n));
            }
        }
        if (!split) {
            OctreeNode& leaf = tree.nodes[item.node];
            leaf = OctreeNode{centre, uint32_t(tree.prim_ids.size()), uint32_t(n), true};
            for (const SpatialRef& r : item.refs) tree.prim_ids.push_back(r.tri);
            ++st.leaves;
            if (n == 0) ++st.empty_leaves;
            if (item.depth >= uint32_t(config.max_depth) && n > size_t(config.leaf_size)) ++st.leaves_at_depth_limit;
            st.max_depth = std::max(st.max_depth, item.depth);
            st.max_leaf_size = std::max(st.max_leaf_size, uint32_t(n));
            continue;
        }
        const uint32_t first = uint32_t(tree.nodes.size());
        tree.nodes[item.node] = OctreeNode{centre, first, 0, false};
        tree.nodes.resize(tree.nodes.size() + 8);
        // Octant 7 pushed first, so octant 0 is built first: depth-first order.
        for (int o = 7; o >= 0; --o)
            work.push_back({first + uint32_t(o), item.depth + 1, octant_box(item.box, centre, o),
                            std::move(children[size_t(o)])});
        item.refs = {};
    }

    tree.end_build(mesh,
                   {.parts = "cells",
                    .leaves_at_depth_limit = st.leaves_at_depth_limit,
                    .depth_limit = config.max_depth,
                    .leaf_size = config.leaf_size,
                    .not_split = no_progress,
                    .not_split_why = "every non-empty octant would hold all of their triangles",
                    .budget_hit = budget_hit,
                    .max_duplication = config.max_duplication},
                   start);
    return tree;
}

bool Octree::intersect_any(const Ray& ray) const {
    NoObserver none;
    return intersect_closest(ray, none).found();
}

nlohmann::json Octree::config() const {
    const OctreeConfig& c = build_config;
    return {{"max_depth", c.max_depth},
            {"leaf_size", c.leaf_size},
            {"clip", std::string(to_string(c.clip))},
            {"mailbox", c.mailbox}};
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
