// The lecture's two heuristics for splitting a BVH node: the longest axis at its middle, or at the median triangle.
#include "core/accel/bvh_splitter.h"

namespace accelviz::bvh_detail {
namespace {

// ---------------------------------------------------------------------------
// [SECTION] Heuristic 1: split the longest axis at its middle
// ---------------------------------------------------------------------------

class MidpointSplitter final : public InPlaceSplitter {
public:
    using InPlaceSplitter::InPlaceSplitter;
    bool uses_sah() const override { return false; }

    SplitChoice find_split(Range range, const Aabb&, const Aabb& centroid_bounds, BuildStep*) override {
        SplitChoice choice;
        choice.axis = longest_axis(centroid_bounds);
        if (choice.axis < 0) return {};
        choice.found = true;
        choice.position = (centroid_bounds.lo[choice.axis] + centroid_bounds.hi[choice.axis]) * 0.5f;
        for (uint32_t k = range.begin; k < range.end; ++k)
            choice.left_count += refs_[k].centroid()[choice.axis] < choice.position ? 1 : 0;
        if (choice.left_count == 0 || choice.left_count == range.count()) {
            // The centroid bounds are so thin that their middle rounds onto an end:
            // split at the median instead, which always leaves both sides non-empty.
            choice.median_fallback = true;
            choice.position = nth_element_median(range, choice.axis);
            choice.left_count = range.count() / 2;
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
// [SECTION] Heuristic 2: split the longest axis at the median triangle
// ---------------------------------------------------------------------------

class MedianSplitter final : public InPlaceSplitter {
public:
    using InPlaceSplitter::InPlaceSplitter;
    bool uses_sah() const override { return false; }

    SplitChoice find_split(Range range, const Aabb&, const Aabb& centroid_bounds, BuildStep*) override {
        SplitChoice choice;
        choice.axis = longest_axis(centroid_bounds);
        if (choice.axis < 0) return {};
        choice.found = true;
        choice.position = nth_element_median(range, choice.axis);  // the partition itself
        choice.left_count = range.count() / 2;
        return choice;
    }

    uint32_t partition(Range range, const SplitChoice& choice, ChildBounds&) override {
        return range.begin + choice.left_count;
    }
};

}  // namespace

std::unique_ptr<Splitter> make_midpoint_splitter(PrimRefs refs) { return std::make_unique<MidpointSplitter>(std::move(refs)); }
std::unique_ptr<Splitter> make_median_splitter(PrimRefs refs) { return std::make_unique<MedianSplitter>(std::move(refs)); }

}  // namespace accelviz::bvh_detail
