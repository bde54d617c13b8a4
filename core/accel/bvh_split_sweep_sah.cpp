// Full-sweep SAH: every centroid on every axis is a candidate plane.
#include "core/accel/bvh_splitter.h"

#include <numeric>

#include <tbb/parallel_invoke.h>

namespace accelviz::bvh_detail {
namespace {

// ---------------------------------------------------------------------------
// [SECTION] Full-sweep SAH: every centroid position on every axis. The triangles
// are sorted once per axis; a split keeps each axis's order (stable partition),
// so every node's range stays sorted on all three axes (Wald 2007, section 3).
// ---------------------------------------------------------------------------

class SweepSahSplitter final : public Splitter {
public:
    SweepSahSplitter(PrimRefs refs, SahCostModel model) : shared_(std::make_shared<Shared>()), s_(*shared_), model_(model) {
        s_.refs = std::move(refs);
        const size_t n = s_.refs.size();
        s_.goes_left.resize(n, 0);
        s_.scratch.resize(n);
        s_.right_area.resize(n);
        // The three sorts are independent (and each a total order: ties by id).
        auto sort_axis = [&](int axis) {
            s_.order[axis].resize(n);
            std::iota(s_.order[axis].begin(), s_.order[axis].end(), 0u);
            std::sort(s_.order[axis].begin(), s_.order[axis].end(), [&](uint32_t a, uint32_t b) {
                const float ca = s_.refs[a].center[axis], cb = s_.refs[b].center[axis];
                return ca < cb || (ca == cb && s_.refs[a].id < s_.refs[b].id);
            });
        };
        tbb::parallel_invoke([&] { sort_axis(0); }, [&] { sort_axis(1); }, [&] { sort_axis(2); });
    }
    SweepSahSplitter(const SweepSahSplitter& other) : Splitter(other), shared_(other.shared_), s_(*shared_), model_(other.model_) {}
    SweepSahSplitter& operator=(const SweepSahSplitter&) = delete;
    /// Every array is either indexed by triangle id or by position in a range, so forks
    /// working on disjoint ranges share them all.
    std::unique_ptr<Splitter> fork() const override { return std::make_unique<SweepSahSplitter>(*this); }
    bool uses_sah() const override { return true; }

    void measure(Range range, Aabb& bounds, Aabb& centroid_bounds) const override {
        Box4 box;
        centroid_bounds = {};
        for (uint32_t k = range.begin; k < range.end; ++k) {
            const uint32_t r = s_.order[0][k];
            box.grow(s_.refs[r].box);
            centroid_bounds.grow(s_.refs[r].center);
        }
        bounds = box.aabb();
    }

    SplitChoice find_split(Range range, const Aabb& bounds, const Aabb& centroid_bounds, BuildStep* step) override {
        SplitChoice best;
        const float area = bounds.area();
        const uint32_t n = range.count();
        for (int axis = 0; axis < 3; ++axis) {
            if (!(centroid_bounds.hi[axis] > centroid_bounds.lo[axis])) continue;
            const uint32_t* order = s_.order[axis].data() + range.begin;
            const PrimRefs& refs = s_.refs;
            // Suffix areas: right_area[i] is the area of the boxes of order[i .. n).
            float* right_area = s_.right_area.data() + range.begin;
            Box4 right;
            for (uint32_t i = n - 1; i >= 1; --i) {
                right.grow(refs[order[i]].box);
                right_area[i] = right.area();
            }
            // Prefix boxes; the plane before position i puts order[0 .. i) on the left. It
            // exists only between two different centroid values.
            Box4 left;
            for (uint32_t i = 1; i < n; ++i) {
                left.grow(refs[order[i - 1]].box);
                const float before = refs[order[i - 1]].center[axis], after = refs[order[i]].center[axis];
                const float cost =
                    before < after ? model_.split_cost(area, left.area(), i, right_area[i], n - i) : kInfinity;
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
    uint32_t prim_id(uint32_t k) const override { return s_.refs[s_.order[0][k]].id; }

private:
    /// The first `left_count` of axis `axis`'s order go left; the other two
    /// axes' orders are stably partitioned to match, so they stay sorted.
    uint32_t split_orders(Range range, int axis, uint32_t left_count) {
        const uint32_t mid = range.begin + left_count;
        uint8_t* goes_left = s_.goes_left.data();
        for (uint32_t k = range.begin; k < range.end; ++k) goes_left[s_.order[axis][k]] = k < mid ? 1 : 0;
        uint32_t* scratch = s_.scratch.data() + range.begin;
        for (int other = 0; other < 3; ++other) {
            if (other == axis) continue;
            uint32_t* order = s_.order[other].data();
            uint32_t left = range.begin, right = 0;
            for (uint32_t k = range.begin; k < range.end; ++k) {
                if (goes_left[order[k]]) order[left++] = order[k];
                else scratch[right++] = order[k];
            }
            std::copy(scratch, scratch + right, order + left);
        }
        return mid;
    }

    /// What the forks share.
    struct Shared {
        PrimRefs refs;  ///< by triangle id; never moved
        std::array<std::vector<uint32_t>, 3> order;  ///< per axis: refs sorted by centroid within each node range
        std::vector<uint8_t> goes_left;  ///< by triangle id
        std::vector<uint32_t> scratch;   ///< by position (a range's partition uses its own positions)
        std::vector<float> right_area;   ///< by position, likewise
    };
    std::shared_ptr<Shared> shared_;
    Shared& s_;
    SahCostModel model_;
};

}  // namespace

std::unique_ptr<Splitter> make_sweep_sah_splitter(PrimRefs refs, SahCostModel model) {
    return std::make_unique<SweepSahSplitter>(std::move(refs), model);
}

}  // namespace accelviz::bvh_detail
