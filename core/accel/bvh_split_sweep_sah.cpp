// Full-sweep SAH: every centroid on every axis is a candidate plane.
#include "core/accel/bvh_splitter.h"

#include <numeric>

namespace accelviz::bvh_detail {
namespace {

// ---------------------------------------------------------------------------
// [SECTION] Full-sweep SAH: every centroid position on every axis. The triangles
// are sorted once per axis; a split keeps each axis's order (stable partition),
// so every node's range stays sorted on all three axes (Wald 2007, section 3).
// ---------------------------------------------------------------------------

class SweepSahSplitter final : public Splitter {
public:
    SweepSahSplitter(PrimRefs refs, SahCostModel model)
        : refs_(std::move(refs)), model_(model), goes_left_(refs_.size(), 0), scratch_(refs_.size()),
          right_area_(refs_.size()) {
        for (int axis = 0; axis < 3; ++axis) {
            order_[axis].resize(refs_.size());
            std::iota(order_[axis].begin(), order_[axis].end(), 0u);
            std::sort(order_[axis].begin(), order_[axis].end(), [&](uint32_t a, uint32_t b) {
                const float ca = refs_[a].center[axis], cb = refs_[b].center[axis];
                return ca < cb || (ca == cb && refs_[a].id < refs_[b].id);
            });
        }
    }
    bool uses_sah() const override { return true; }

    void measure(Range range, Aabb& bounds, Aabb& centroid_bounds) const override {
        Box4 box;
        centroid_bounds = {};
        for (uint32_t k = range.begin; k < range.end; ++k) {
            const uint32_t r = order_[0][k];
            box.grow(refs_[r].box);
            centroid_bounds.grow(refs_[r].center);
        }
        bounds = box.aabb();
    }

    SplitChoice find_split(Range range, const Aabb& bounds, const Aabb& centroid_bounds, BuildStep* step) override {
        SplitChoice best;
        const float area = bounds.area();
        const uint32_t n = range.count();
        for (int axis = 0; axis < 3; ++axis) {
            if (!(centroid_bounds.hi[axis] > centroid_bounds.lo[axis])) continue;
            const uint32_t* order = order_[axis].data() + range.begin;
            // Suffix areas: right_area_[i] is the area of the boxes of order[i .. n).
            Box4 right;
            for (uint32_t i = n - 1; i >= 1; --i) {
                right.grow(refs_[order[i]].box);
                right_area_[i] = right.area();
            }
            // Prefix boxes; the plane before position i puts order[0 .. i) on the left. It
            // exists only between two different centroid values.
            Box4 left;
            for (uint32_t i = 1; i < n; ++i) {
                left.grow(refs_[order[i - 1]].box);
                const float before = refs_[order[i - 1]].center[axis], after = refs_[order[i]].center[axis];
                const float cost =
                    before < after ? model_.split_cost(area, left.area(), i, right_area_[i], n - i) : kInfinity;
                if (step) {
                    step->candidate_positions[axis].push_back(after);
                    step->candidate_costs[axis].push_back(cost);
                }
                if (is_better_split(cost, i, best.cost, best.left_count, n))
                    best = {.found = true, .axis = axis, .position = after, .left_count = i, .cost = cost, .index = i};
            }
        }
        return best;
    }

    uint32_t partition(Range range, const SplitChoice& choice, ChildBounds&) override {
        return split_orders(range, choice.axis, choice.left_count);
    }
    uint32_t partition_in_half(Range range) override { return split_orders(range, 0, range.count() / 2); }
    uint32_t prim_id(uint32_t k) const override { return refs_[order_[0][k]].id; }

private:
    /// The first `left_count` of axis `axis`'s order go left; the other two
    /// axes' orders are stably partitioned to match, so they stay sorted.
    uint32_t split_orders(Range range, int axis, uint32_t left_count) {
        const uint32_t mid = range.begin + left_count;
        for (uint32_t k = range.begin; k < range.end; ++k) goes_left_[order_[axis][k]] = k < mid ? 1 : 0;
        for (int other = 0; other < 3; ++other) {
            if (other == axis) continue;
            uint32_t* order = order_[other].data();
            uint32_t left = range.begin, right = 0;
            for (uint32_t k = range.begin; k < range.end; ++k) {
                if (goes_left_[order[k]]) order[left++] = order[k];
                else scratch_[right++] = order[k];
            }
            std::copy(scratch_.begin(), scratch_.begin() + right, order + left);
        }
        return mid;
    }

    PrimRefs refs_;  ///< by triangle id; never moved
    SahCostModel model_;
    std::array<std::vector<uint32_t>, 3> order_;  ///< per axis: refs sorted by centroid within each node range
    std::vector<uint8_t> goes_left_;
    std::vector<uint32_t> scratch_;
    std::vector<float> right_area_;
};

}  // namespace

std::unique_ptr<Splitter> make_sweep_sah_splitter(PrimRefs refs, SahCostModel model) {
    return std::make_unique<SweepSahSplitter>(std::move(refs), model);
}

}  // namespace accelviz::bvh_detail
