// The lecture's two heuristics for splitting a BVH node: the longest centroid axis
// cut at its middle, or at the median triangle.
#include "core/accel/bvh_splitter.h"

namespace accelviz::bvh_detail {
namespace {

/// The lecture's heuristic 1: cut the longest axis of the node's centroids. The two
/// builders differ in where they cut it (heuristic 2: at its middle, or at the median).
class LongestAxisSplitter : public InPlaceSplitter {
public:
    using InPlaceSplitter::InPlaceSplitter;
    bool uses_sah() const override { return false; }

protected:
    /// The cut at the median triangle on `axis`: half the triangles on each side.
    /// nth_element puts them in place, so the partition is already done.
    SplitChoice median_cut(Range range, int axis) {
        SplitChoice choice;
        choice.found = true;
        choice.axis = axis;
        choice.position = nth_element_median(range, axis);
        choice.left_count = range.count() / 2;
        return choice;
    }
};

// ---------------------------------------------------------------------------
// [SECTION] Split the longest axis at its middle
// ---------------------------------------------------------------------------

class MidpointSplitter final : public LongestAxisSplitter {
public:
    using LongestAxisSplitter::LongestAxisSplitter;
    std::unique_ptr<Splitter> fork() const override { return std::make_unique<MidpointSplitter>(*this); }

    SplitChoice find_split(Range range, const Aabb&, const Aabb& centroid_bounds, BuildStep*) override {
        const int axis = longest_axis(centroid_bounds);
        if (axis < 0) return {};
        SplitChoice choice;
        choice.found = true;
        choice.axis = axis;
        choice.position = (centroid_bounds.lo[axis] + centroid_bounds.hi[axis]) * 0.5f;
        for (uint32_t k = range.begin; k < range.end; ++k)
            choice.left_count += refs_[k].centroid()[axis] < choice.position ? 1 : 0;
        if (choice.left_count == 0 || choice.left_count == range.count()) {
            // The centroid bounds are so thin that their middle rounds onto an end:
            // split at the median instead, which always leaves both sides non-empty.
            choice = median_cut(range, axis);
            choice.median_fallback = true;
        }
        return choice;
    }

    uint32_t partition(Range range, const SplitChoice& choice, ChildBounds&) override {
        if (choice.median_fallback) return range.begin + choice.left_count;  // nth_element already did it
        const auto mid = std::partition(refs_.begin() + range.begin, refs_.begin() + range.end,
                                        [&](const PrimRef& r) { return r.centroid()[choice.axis] < choice.position; });
        return uint32_t(mid - refs_.begin());
    }
};

// ---------------------------------------------------------------------------
// [SECTION] Split the longest axis at the median triangle
// ---------------------------------------------------------------------------

class MedianSplitter final : public LongestAxisSplitter {
public:
    using LongestAxisSplitter::LongestAxisSplitter;
    std::unique_ptr<Splitter> fork() const override { return std::make_unique<MedianSplitter>(*this); }

    SplitChoice find_split(Range range, const Aabb&, const Aabb& centroid_bounds, BuildStep*) override {
        const int axis = longest_axis(centroid_bounds);
        return axis < 0 ? SplitChoice{} : median_cut(range, axis);
    }

    uint32_t partition(Range range, const SplitChoice& choice, ChildBounds&) override {
        return range.begin + choice.left_count;
    }
};

}  // namespace

std::unique_ptr<Splitter> make_midpoint_splitter(PrimRefs refs) { return std::make_unique<MidpointSplitter>(std::move(refs)); }
std::unique_ptr<Splitter> make_median_splitter(PrimRefs refs) { return std::make_unique<MedianSplitter>(std::move(refs)); }

}  // namespace accelviz::bvh_detail
