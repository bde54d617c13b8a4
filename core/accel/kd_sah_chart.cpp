#include "core/accel/kd_sah_chart.h"

#include <algorithm>

#include "core/accel/kd_sah.h"

namespace accelviz {

KdSahChart kd_sah_chart(const Mesh& mesh, const KdTree& tree, uint32_t node, const KdConfig& config,
                        size_t max_points) {
    KdSahChart chart;
    chart.node = node;
    chart.config = config;
    if (node >= tree.nodes.size()) return chart;

    // The path from the root: each node's parent (the build makes both children at once).
    std::vector<uint32_t> parent(tree.nodes.size(), UINT32_MAX);
    for (uint32_t i = 0; i < tree.nodes.size(); ++i)
        if (!tree.nodes[i].is_leaf()) parent[tree.nodes[i].lower_child()] = parent[tree.nodes[i].upper_child()] = i;
    std::vector<uint32_t> path = {node};
    while (parent[path.back()] != UINT32_MAX) path.push_back(parent[path.back()]);
    std::reverse(path.begin(), path.end());

    // The references down the path, as the build cut them.
    const float pad = tree.build_stats.padding;
    SpatialRefs refs = root_references(mesh, pad), next;
    const CornerTriples triangles = corner_triples(mesh);
    Aabb cell = tree.bounds;
    for (size_t k = 0; k + 1 < path.size(); ++k) {
        const KdNode& p = tree.nodes[path[k]];
        const bool lower = path[k + 1] == p.lower_child();
        next.clear();
        Vec3 planes;
        planes[p.axis()] = p.split();
        ChildRefs parts;
        for (const SpatialRef& r : refs) {
            split_reference(r, triangles, cell, planes, 1u << p.axis(), pad, part_rule(tree.build_config.clip), parts);
            for (int k = 0; k < parts.count; ++k)
                if ((parts.child[k] != 0) != lower) next.push_back(parts.ref[k]);
        }
        refs.swap(next);
        if (lower) cell.hi[p.axis()] = p.split();
        else cell.lo[p.axis()] = p.split();
    }
    chart.cell = cell;
    chart.count = uint32_t(refs.size());
    chart.leaf_cost = config.cost_isect * float(kd_tests(config, refs.size()));
    for (int a = 0; a < 3; ++a) {
        chart.axes[size_t(a)].lo = cell.lo[a];
        chart.axes[size_t(a)].hi = cell.hi[a];
    }

    // Every candidate, and the cheapest by the builder's rule (the first of the lowest cost).
    std::vector<float> los, his;
    SortScratch scratch;
    double best = kInfinity;
    sweep_kd_sah(refs, cell, config, los, his, scratch, [&](int a, float s, size_t below, size_t above, double cost) {
        KdSahChartAxis& axis = chart.axes[size_t(a)];
        axis.positions.push_back(s);
        axis.costs.push_back(float(cost));
        axis.below.push_back(uint32_t(below));
        axis.above.push_back(uint32_t(above));
        if (cost < best) {
            best = cost;
            chart.best_axis = a;
            chart.best_position = s;
            chart.best_below = uint32_t(below);
            chart.best_above = uint32_t(above);
        }
    });
    chart.best_cost = chart.best_axis >= 0 ? float(best) : kInfinity;

    // A chart has no more points than pixels: keep the cheapest of each run.
    for (KdSahChartAxis& axis : chart.axes) {
        axis.candidates = axis.positions.size();
        if (max_points == 0 || axis.candidates <= max_points) continue;
        const size_t stride = (axis.candidates + max_points - 1) / max_points;
        size_t out = 0;
        for (size_t begin = 0; begin < axis.candidates; begin += stride) {
            const size_t end = std::min(axis.candidates, begin + stride);
            size_t pick = begin;
            for (size_t i = begin + 1; i < end; ++i)
                if (axis.costs[i] < axis.costs[pick]) pick = i;
            axis.positions[out] = axis.positions[pick];
            axis.costs[out] = axis.costs[pick];
            axis.below[out] = axis.below[pick];
            axis.above[out] = axis.above[pick];
            ++out;
        }
        axis.positions.resize(out);
        axis.costs.resize(out);
        axis.below.resize(out);
        axis.above.resize(out);
        axis.subsampled = true;
    }
    return chart;
}

}  // namespace accelviz
