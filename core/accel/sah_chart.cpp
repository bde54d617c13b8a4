#include "core/accel/sah_chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

namespace accelviz {
namespace {

/// A triangle as the builder sees it: its box and its centroid, computed exactly
/// as bvh_build.cpp does (so the costs come out bit for bit the same).
struct Ref {
    Aabb box;
    Vec3 center;
    uint32_t id;
};

/// The refs sorted by centroid on `axis`, ties by id (the sweep's and the median's order).
std::vector<uint32_t> sorted_on(const std::vector<Ref>& refs, int axis) {
    std::vector<uint32_t> order(refs.size());
    std::iota(order.begin(), order.end(), 0u);
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        const float ca = refs[a].center[axis], cb = refs[b].center[axis];
        return ca < cb || (ca == cb && refs[a].id < refs[b].id);
    });
    return order;
}

/// SAH cost of sending the first `left` refs of `order` left, the rest right.
float cut_cost(const std::vector<Ref>& refs, const std::vector<uint32_t>& order, uint32_t left, const SahCostModel& model,
               float area) {
    Aabb a, b;
    for (uint32_t k = 0; k < order.size(); ++k) (k < left ? a : b).grow(refs[order[k]].box);
    return model.split_cost(area, a.area(), left, b.area(), uint32_t(order.size()) - left);
}

/// Where the median builder cuts: the longest centroid axis, the first n/2 by centroid.
HeuristicCut median_cut(const std::vector<Ref>& refs, int axis, const SahCostModel& model, float area) {
    HeuristicCut cut;
    if (axis < 0) return cut;
    const std::vector<uint32_t> order = sorted_on(refs, axis);
    const auto n = uint32_t(refs.size());
    cut.valid = true;
    cut.axis = axis;
    cut.left_count = n / 2;
    cut.position = refs[order[n / 2]].center[axis];
    cut.cost = cut_cost(refs, order, cut.left_count, model, area);
    return cut;
}

/// Where the midpoint builder cuts: the middle of the longest centroid axis
/// (the median if that leaves a side empty, as the builder does).
HeuristicCut midpoint_cut(const std::vector<Ref>& refs, const Aabb& centroid_bounds, int axis, const SahCostModel& model,
                          float area) {
    HeuristicCut cut;
    if (axis < 0) return cut;
    const float position = (centroid_bounds.lo[axis] + centroid_bounds.hi[axis]) * 0.5f;
    uint32_t left = 0;
    for (const Ref& r : refs) left += r.center[axis] < position ? 1 : 0;
    if (left == 0 || left == refs.size()) {
        cut = median_cut(refs, axis, model, area);
        cut.median_fallback = true;
        return cut;
    }
    Aabb a, b;
    for (const Ref& r : refs) (r.center[axis] < position ? a : b).grow(r.box);
    cut.valid = true;
    cut.axis = axis;
    cut.position = position;
    cut.left_count = left;
    cut.cost = model.split_cost(area, a.area(), left, b.area(), uint32_t(refs.size()) - left);
    return cut;
}

/// The chart's best plane so far, across the three axes, of a node of `count`
/// triangles: the same rule as the builder (is_better_split: cheaper, or as cheap and more even).
void keep_if_best(SahChart& chart, float cost, int axis, float position, uint32_t left_count, uint32_t count,
                  const Aabb& left, const Aabb& right) {
    if (cost == chart.best_cost && cost < kInfinity &&
        larger_side(left_count, count) != larger_side(chart.best_left_count, count))
        chart.best_tied = true;
    else if (cost < chart.best_cost)
        chart.best_tied = false;
    if (!is_better_split(cost, left_count, chart.best_cost, chart.best_left_count, count)) return;
    chart.best_cost = cost;
    chart.best_axis = axis;
    chart.best_position = position;
    chart.best_left_count = left_count;
    chart.best_children[0] = left;
    chart.best_children[1] = right;
}

/// Binned SAH on one axis, exactly as BinnedSahSplitter: B equal buckets over the
/// centroid extent, plane i has buckets [0, i) on the left.
void binned_axis(const std::vector<Ref>& refs, int axis, int bin_count, const SahCostModel& model, float area,
                 SahChartAxis& out, SahChart& chart) {
    const float origin = out.lo, extent = out.hi - out.lo;
    const float scale = float(bin_count) / extent;
    struct Bin {
        Aabb box;
        uint32_t count = 0;
    };
    const auto b_count = size_t(bin_count);
    std::vector<Bin> bins(b_count);
    for (const Ref& r : refs) {
        const float f = (r.center[axis] - origin) * scale;
        const int b = int(std::min(float(bin_count - 1), std::max(0.0f, f)));
        bins[size_t(b)].box.grow(r.box);
        ++bins[size_t(b)].count;
    }
    std::vector<Aabb> right_box(b_count);
    std::vector<uint32_t> right_count(b_count, 0);
    Aabb right;
    uint32_t count = 0;
    for (int i = bin_count - 1; i >= 1; --i) {
        right.grow(bins[size_t(i)].box);
        count += bins[size_t(i)].count;
        right_box[size_t(i)] = right;
        right_count[size_t(i)] = count;
    }
    Aabb left;
    count = 0;
    out.candidates = size_t(bin_count - 1);
    for (int i = 1; i < bin_count; ++i) {
        left.grow(bins[size_t(i - 1)].box);
        count += bins[size_t(i - 1)].count;
        const float position = origin + float(i) / scale;  // the builder's plane_position
        const bool empty_side = count == 0 || right_count[size_t(i)] == 0;
        const float cost = empty_side ? kInfinity
                                      : model.split_cost(area, left.area(), count, right_box[size_t(i)].area(),
                                                         right_count[size_t(i)]);
        out.positions.push_back(position);
        out.costs.push_back(cost);
        out.left_counts.push_back(count);
        keep_if_best(chart, cost, axis, position, count, uint32_t(refs.size()), left, right_box[size_t(i)]);
    }
}

/// Full sweep on one axis, exactly as SweepSahSplitter: the plane before sorted
/// position i (at that centroid) puts the first i left; none between equal centroids.
void sweep_axis(const std::vector<Ref>& refs, int axis, const SahCostModel& model, float area, size_t max_points,
                SahChartAxis& out, SahChart& chart) {
    const std::vector<uint32_t> order = sorted_on(refs, axis);
    const auto n = uint32_t(order.size());
    std::vector<Aabb> right_box(n);
    Aabb right;
    for (uint32_t i = n - 1; i >= 1; --i) {
        right.grow(refs[order[i]].box);
        right_box[i] = right;
    }
    std::vector<float> positions, costs;
    positions.reserve(n);
    costs.reserve(n);
    Aabb left;
    for (uint32_t i = 1; i < n; ++i) {
        left.grow(refs[order[i - 1]].box);
        const float before = refs[order[i - 1]].center[axis], after = refs[order[i]].center[axis];
        const float cost = before < after ? model.split_cost(area, left.area(), i, right_box[i].area(), n - i) : kInfinity;
        positions.push_back(after);
        costs.push_back(cost);
        keep_if_best(chart, cost, axis, after, i, n, left, right_box[i]);
    }
    out.candidates = positions.size();
    out.stride = 1;
    if (max_points > 0 && positions.size() > max_points) {
        out.subsampled = true;
        out.stride = (positions.size() + max_points - 1) / max_points;
    }
    // Each listed candidate is the best of its run of `stride` (the builder's rule).
    for (size_t start = 0; start < positions.size(); start += out.stride) {
        const size_t end = std::min(positions.size(), start + out.stride);
        size_t pick = start;
        for (size_t k = start + 1; k < end; ++k)
            if (is_better_split(costs[k], uint32_t(k + 1), costs[pick], uint32_t(pick + 1), n)) pick = k;
        out.positions.push_back(positions[pick]);
        out.costs.push_back(costs[pick]);
        out.left_counts.push_back(uint32_t(pick + 1));
    }
}

std::string format_cost(float cost) {
    char text[32];
    std::snprintf(text, sizeof text, std::abs(cost) >= 1000.0f ? "%.0f" : "%.4g", double(cost));
    return text;
}

void write_verdict(SahChart& chart) {
    const uint32_t n = chart.count;
    const bool fits = n <= uint32_t(chart.max_leaf_size);
    const bool sah = chart.builder == BvhBuilder::SahBinned || chart.builder == BvhBuilder::SahSweep;
    const std::string leaf = format_cost(chart.leaf_cost), best = format_cost(chart.best_cost);
    const std::string limit = std::to_string(chart.max_leaf_size);
    const std::string tie = chart.best_tied ? " (other planes cost the same: the most even one is taken)" : "";
    auto set = [&](ChartVerdict v, std::string text) {
        chart.verdict = v;
        chart.verdict_text = std::move(text);
    };
    if (n <= 1) return set(ChartVerdict::LeafOneTriangle, n == 0 ? "No triangles." : "One triangle: always a leaf.");
    const bool plane = chart.best_axis >= 0;
    if (!sah) {
        if (fits) return set(ChartVerdict::LeafFits, std::to_string(n) + " triangles fit in a leaf (at most " + limit + ").");
        if (!chart.midpoint.valid)
            return set(ChartVerdict::SplitInHalf,
                       "All centroids are equal: no plane separates them; the range is split in half by index.");
        return set(ChartVerdict::Split, std::to_string(n) + " triangles do not fit in a leaf (at most " + limit +
                                            "): split at the " + std::string(to_string(chart.builder)) + " plane.");
    }
    if (plane && chart.best_cost < chart.leaf_cost)
        return set(ChartVerdict::Split, "Split: the cheapest plane costs " + best + " < leaf " + leaf + tie + ".");
    if (!plane) {
        const std::string why = "All centroids are equal: no plane separates them";
        if (fits) return set(ChartVerdict::LeafNoPlane, why + "; a leaf (" + std::to_string(n) + " <= " + limit + ").");
        return set(ChartVerdict::SplitInHalf, why + "; too many for a leaf, so the range is split in half by index.");
    }
    const std::string why = "No split helps: the cheapest plane costs " + best + " >= leaf " + leaf;
    if (fits) return set(ChartVerdict::LeafCheaper, why + ": a leaf.");
    return set(ChartVerdict::SplitForcedBySize,
               why + ", but " + std::to_string(n) + " > " + limit + " triangles: the cheapest split anyway" + tie + ".");
}

}  // namespace

SahChart compute_sah_chart(const Mesh& mesh, std::span<const uint32_t> prim_ids, const BvhConfig& requested,
                           const SahChartOptions& options) {
    const BvhConfig& config = requested;
    SahChart chart;
    if (auto err = validate(config)) {
        chart.verdict_text = "No chart: " + err->message;
        return chart;
    }
    chart.builder = config.builder;
    chart.sweep = config.builder == BvhBuilder::SahSweep;
    chart.bins = config.bins;
    chart.model = config.sah_model();
    chart.max_leaf_size = config.max_leaf_size;
    chart.count = uint32_t(prim_ids.size());
    chart.leaf_cost = chart.model.leaf_cost(chart.count);

    std::vector<Ref> refs;
    refs.reserve(prim_ids.size());
    for (uint32_t id : prim_ids) {
        const Vec3 p0 = mesh.vertex(id, 0), p1 = mesh.vertex(id, 1), p2 = mesh.vertex(id, 2);
        const Ref r{triangle_box(p0, p1, p2), (p0 + p1 + p2) / 3.0f, id};
        chart.bounds.grow(r.box);
        chart.centroid_bounds.grow(r.center);
        refs.push_back(r);
    }
    if (refs.empty()) {
        write_verdict(chart);
        return chart;
    }
    const float area = chart.bounds.area();
    for (int axis = 0; axis < 3; ++axis) {
        SahChartAxis& a = chart.axes[size_t(axis)];
        a.lo = chart.centroid_bounds.lo[axis];
        a.hi = chart.centroid_bounds.hi[axis];
        a.usable = a.hi > a.lo;
        if (!a.usable || refs.size() < 2) continue;
        if (chart.sweep)
            sweep_axis(refs, axis, chart.model, area, options.max_points, a, chart);
        else
            binned_axis(refs, axis, chart.bins, chart.model, area, a, chart);
    }
    const Vec3 extent = chart.centroid_bounds.extent();
    const int longest = extent[max_axis(extent)] > 0.0f ? max_axis(extent) : -1;
    chart.median = median_cut(refs, longest, chart.model, area);
    chart.midpoint = midpoint_cut(refs, chart.centroid_bounds, longest, chart.model, area);
    write_verdict(chart);
    return chart;
}

std::string explain(BuildDecision decision, int max_leaf_size) {
    const std::string limit = std::to_string(max_leaf_size);
    switch (decision) {
        case BuildDecision::LeafFits: return "Leaf: the node fits (at most " + limit + " triangles).";
        case BuildDecision::LeafCheaper: return "Leaf: no split is cheaper than the leaf, and the leaf fits.";
        case BuildDecision::LeafNoSeparatingPlane:
            return "Leaf: all centroids are equal, so no plane separates them (and the leaf fits).";
        case BuildDecision::LeafDepthLimit: return "Leaf: a split would make the tree deeper than the traversal stack allows.";
        case BuildDecision::Split: return "Split: the builder's own plane.";
        case BuildDecision::SplitForcedBySize:
            return "Split although the leaf is cheaper: a leaf may hold at most " + limit + " triangles.";
        case BuildDecision::SplitMedianFallback:
            return "Split at the median: the middle plane rounded onto one end of the centroid bounds.";
        case BuildDecision::SplitInHalfCentroidsEqual:
            return "Split in half by index: all centroids are equal, no plane separates them, and the leaf is too big.";
        case BuildDecision::SplitInHalfDepthBudget:
            return "Split in half by index: the builder's split could make the tree too deep.";
    }
    return "";
}

}  // namespace accelviz
