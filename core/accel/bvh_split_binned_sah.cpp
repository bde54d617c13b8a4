// Binned SAH: the BVH builder the lecture recommends (B < 32 buckets per axis).
#include "core/accel/bvh_splitter.h"

#include <bit>
#include <cmath>

#include "core/util/prefetch.h"

namespace accelviz::bvh_detail {
namespace {

// ---------------------------------------------------------------------------
// [SECTION] Binned SAH (lecture: 高效地实现分区; Wald, "On fast Construction of
// SAH-based Bounding Volume Hierarchies", 2007)
// ---------------------------------------------------------------------------

/// The bucket of a triangle's centroid on each axis, clamped to [0, B-1] (NaN lands
/// in 0): (c - origin) · scale, truncated. The three axes at once (SSE where available).
struct BinIndices {
    int index[4];
};
struct BinMap {
    alignas(16) float origin[4] = {0, 0, 0, 0};  ///< the centroid bounds' low corner; [3] unused
    alignas(16) float scale[4] = {0, 0, 0, 0};   ///< B / extent per axis (0 for an unusable axis); [3] stays 0
    float last_bin = 0;                          ///< B - 1

    BinIndices operator()(const PrimRef& ref) const {
        BinIndices b;
#if defined(__SSE2__)
        const __m128 f = _mm_mul_ps(_mm_sub_ps(load_xyz(&ref.center.x), _mm_load_ps(origin)), _mm_load_ps(scale));
        const __m128 clamped = _mm_min_ps(_mm_max_ps(f, _mm_setzero_ps()), _mm_set1_ps(last_bin));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(b.index), _mm_cvttps_epi32(clamped));
#else
        for (int axis = 0; axis < 3; ++axis) {
            const float f = (ref.center[axis] - origin[axis]) * scale[axis];
            b.index[axis] = int(std::min(last_bin, std::max(0.0f, f)));  // max(0, NaN) = 0
        }
#endif
        return b;
    }
};

class BinnedSahSplitter final : public InPlaceSplitter {
public:
    BinnedSahSplitter(PrimRefs refs, int bins, SahCostModel model)
        : InPlaceSplitter(std::move(refs)), bin_count_(bins), model_(model) {}
    /// The bins are empty between nodes, so a copy starts clean.
    std::unique_ptr<Splitter> fork() const override { return std::make_unique<BinnedSahSplitter>(*this); }
    bool uses_sah() const override { return true; }

    SplitChoice find_split(Range range, const Aabb& bounds, const Aabb& centroid_bounds, BuildStep* step) override {
        // Bins divide the centroid bounds of each axis into B equal buckets. An axis
        // whose centroids all coincide has nothing to divide and is skipped.
        bool usable[3] = {false, false, false};
        for (int axis = 0; axis < 3; ++axis) {
            const float extent = centroid_bounds.hi[axis] - centroid_bounds.lo[axis];
            usable[axis] = extent > 0.0f;
            map_.origin[axis] = centroid_bounds.lo[axis];
            map_.scale[axis] = usable[axis] ? float(bin_count_) / extent : 0.0f;
        }
        if (!usable[0] && !usable[1] && !usable[2]) return {};
        map_.last_bin = float(bin_count_ - 1);
        const BinMap map = map_;  // a local copy the loops keep in registers

        if (range.count() <= kFewTriangles && !step) return find_split_among_few(range, bounds, usable);

        // One pass: each triangle lands in one bin per axis (lecture: compute_bucket).
        // `used` marks the non-empty bins: most nodes are small, and then a sweep over
        // only those bins is much cheaper than over all B. Neighbouring triangles often
        // land in the same bin, and growing a bin's box must wait for the previous
        // growth of that box: in big nodes even and odd positions fill two sets of
        // bins, merged after; there the bins' counts say which are used (cheaper than
        // marking them per triangle, since all B of them usually are).
        uint64_t used[3] = {0, 0, 0};
        auto drop = [&](int set, const PrimRef& ref, bool mark_used) {
            const BinIndices b = map(ref);
            for (int axis = 0; axis < 3; ++axis) {
                if (!usable[axis]) continue;
                Bin& bin = bins_[set][axis][b.index[axis]];
                bin.box.grow(ref.box);
                ++bin.count;
                if (mark_used) used[axis] |= uint64_t(1) << b.index[axis];
            }
        };
        if (range.count() >= kTwoBinSets) {
            uint32_t k = range.begin;
            for (; k + 1 < range.end; k += 2) {
                drop(0, refs_[k], false);
                drop(1, refs_[k + 1], false);
            }
            if (k < range.end) drop(0, refs_[k], false);
            for (int axis = 0; axis < 3; ++axis) {
                if (!usable[axis]) continue;
                for (int i = 0; i < bin_count_; ++i) {
                    Bin& bin = bins_[0][axis][i];
                    Bin& odd = bins_[1][axis][i];
                    if (odd.count != 0) {
                        bin.box.grow(odd.box);
                        bin.count += odd.count;
                        odd = {};
                    }
                    if (bin.count != 0) used[axis] |= uint64_t(1) << i;
                }
            }
        } else {
            for (uint32_t k = range.begin; k < range.end; ++k) drop(0, refs_[k], true);
        }

        // The plane i has bins [0, i) on the left and [i, B) on the right. Between two
        // non-empty bins every plane splits the triangles alike; the first such plane
        // stands for them all (it also wins their tie).
        SplitChoice best;
        const float area = bounds.area();
        for (int axis = 0; axis < 3; ++axis) {
            if (!usable[axis]) continue;
            Bin* bin = bins_[0][axis];
            int filled[kMaxBins];  // the non-empty bins, in order
            int filled_count = 0;
            for (uint64_t m = used[axis]; m != 0; m &= m - 1) filled[filled_count++] = std::countr_zero(m);
            // Suffix boxes: right side of the plane before filled[j] holds filled[j ..].
            // Prefix boxes: left side of the same plane holds filled[.. j-1].
            float left_area[kMaxBins], right_area[kMaxBins];
            uint32_t left_count[kMaxBins], right_count[kMaxBins];
            Box4 right;
            uint32_t count = 0;
            for (int j = filled_count - 1; j >= 1; --j) {
                right.grow(bin[filled[j]].box);
                count += bin[filled[j]].count;
                right_area[j] = right.area();
                right_count[j] = count;
            }
            Box4 left;
            count = 0;
            for (int j = 1; j < filled_count; ++j) {
                left.grow(bin[filled[j - 1]].box);
                count += bin[filled[j - 1]].count;
                left_area[j] = left.area();
                left_count[j] = count;
            }
            // The cost of the plane just after each non-empty bin (one loop the compiler
            // vectorizes), then the best (is_better_split).
            float cost_after[kMaxBins];
            for (int j = 1; j < filled_count; ++j)
                cost_after[j] = model_.split_cost(area, left_area[j], left_count[j], right_area[j], right_count[j]);
            for (int j = 1; j < filled_count; ++j) {
                keep_if_better(best, cost_after[j], axis, filled[j - 1] + 1, left_count[j], range.count());
            }
            if (step) {  // every plane for the stepper: +inf where one side is empty
                int j = 0;  // non-empty bins left of plane i
                for (int i = 1; i < bin_count_; ++i) {
                    if (j < filled_count && filled[j] == i - 1) ++j;
                    step->candidate_positions[axis].push_back(plane_position(axis, i));
                    step->candidate_costs[axis].push_back(j == 0 || j == filled_count ? kInfinity : cost_after[j]);
                }
            }
            for (int j = 0; j < filled_count; ++j) bin[filled[j]] = {};  // clean for the next node
        }
        return best;
    }

    /// find_split for a node of at most kFewTriangles triangles, without the bins: the
    /// same planes (one after each non-empty bin but the last), the same boxes, counts
    /// and costs, so the same choice. Per axis the triangles are sorted by bin; a plane
    /// sits wherever the bin changes. Most nodes of a tree are this small, and emptying
    /// B bins per axis and node would cost more than the triangles themselves.
    SplitChoice find_split_among_few(Range range, const Aabb& bounds, const bool usable[3]) const {
        const uint32_t n = range.count();
        const PrimRef* refs = refs_.data() + range.begin;
        BinIndices bins[kFewTriangles];
        const BinMap map = map_;
        for (uint32_t i = 0; i < n; ++i) bins[i] = map(refs[i]);
        SplitChoice best;
        const float area = bounds.area();
        if (n == 2) {
            // Two triangles (over a third of a big tree's nodes): every plane between their
            // bins puts one on each side, in the same two boxes, so all such planes
            // cost the same and the first one found wins (is_better_split): the plane
            // just after the lower bin on the first axis where their bins differ.
            for (int axis = 0; axis < 3; ++axis) {
                const int a = bins[0].index[axis], b = bins[1].index[axis];
                if (!usable[axis] || a == b) continue;
                const Box4& lower = refs[a < b ? 0 : 1].box;
                const Box4& upper = refs[a < b ? 1 : 0].box;
                keep_if_better(best, model_.split_cost(area, lower.area(), 1, upper.area(), 1), axis,
                               std::min(a, b) + 1, 1, n);
                return best;
            }
            return best;
        }
        for (int axis = 0; axis < 3; ++axis) {
            if (!usable[axis]) continue;
            // Positions sorted by bin, ties by position: keys bin · 4 + position (missing
            // triangles sort last) through a sorting network, without branches.
            static_assert(kFewTriangles == 4, "the sorting network sorts four keys");
            int key[4];
            for (uint32_t i = 0; i < 4; ++i) key[i] = i < n ? bins[i].index[axis] * 4 + int(i) : INT32_MAX;
            auto order_pair = [&](int a, int b) {
                const int lo = std::min(key[a], key[b]), hi = std::max(key[a], key[b]);
                key[a] = lo;
                key[b] = hi;
            };
            order_pair(0, 1), order_pair(2, 3), order_pair(0, 2), order_pair(1, 3), order_pair(1, 2);
            uint32_t order[4];
            for (uint32_t i = 0; i < 4; ++i) order[i] = uint32_t(key[i]) & 3;
            auto bin_at = [&](uint32_t i) { return key[i] >> 2; };
            float right_area[kFewTriangles];
            Box4 right;
            for (uint32_t i = n - 1; i >= 1; --i) {  // the plane before position i: order[i ..] on the right
                right.grow(refs[order[i]].box);
                right_area[i] = right.area();
            }
            Box4 left;
            for (uint32_t i = 1; i < n; ++i) {
                left.grow(refs[order[i - 1]].box);
                if (bin_at(i - 1) == bin_at(i)) continue;  // no plane between two triangles of one bin
                keep_if_better(best, model_.split_cost(area, left.area(), i, right_area[i], n - i), axis,
                               bin_at(i - 1) + 1, i, n);
            }
        }
        return best;
    }

    uint32_t partition(Range range, const SplitChoice& choice, ChildBounds& children) override {
        // Lomuto's partition without branches (which side a triangle goes to is a coin
        // toss the branch predictor cannot learn): [begin, store) holds the left side,
        // [store, k) the right; every element is swapped to `store`, and `store` only
        // moves on if it went left. The same bin_index as the binning pass, so exactly
        // left_count triangles go left. Each side's boxes are grown on the way.
        // (The four boxes are grown by masks, not picked by index: an array of two would
        // live in memory and make each growth wait for the last one's store.)
        Box4 left_box, right_box, left_centroids, right_centroids;
        const BinMap map = map_;
        uint32_t store = range.begin;
        for (uint32_t k = range.begin; k < range.end; ++k) {
            const PrimRef ref = refs_[k];
            const bool left = uint32_t(map(ref).index[choice.axis]) < choice.index;
            left_box.grow_if(left, ref.box);
            right_box.grow_if(!left, ref.box);
            left_centroids.grow_point_if(left, &ref.center.x);
            right_centroids.grow_point_if(!left, &ref.center.x);
            refs_[k] = refs_[store];
            refs_[store] = ref;
            store += left ? 1 : 0;
        }
        children = {true, {left_box.aabb(), right_box.aabb()}, {left_centroids.aabb(), right_centroids.aabb()}};
        return store;
    }

private:
    static constexpr int kMaxBins = 64;
    static constexpr uint32_t kFewTriangles = 4;  ///< nodes this small skip the bins (find_split_among_few)
    static constexpr uint32_t kTwoBinSets = 64;    ///< nodes this big bin into two sets (find_split)
    struct Bin {
        Box4 box;
        uint32_t count = 0;
    };

    float plane_position(int axis, int plane) const { return map_.origin[axis] + float(plane) / map_.scale[axis]; }

    /// The plane before bin `plane` on `axis` replaces `best` if it is the better split
    /// of the node's `count` triangles (is_better_split: cheaper, or as cheap and more even).
    void keep_if_better(SplitChoice& best, float cost, int axis, int plane, uint32_t left_count,
                        uint32_t count) const {
        if (!is_better_split(cost, left_count, best.cost, best.left_count, count)) return;
        best = {.found = true, .axis = axis, .position = plane_position(axis, plane), .left_count = left_count,
                .cost = cost, .index = uint32_t(plane)};
    }

    int bin_count_;
    SahCostModel model_;
    BinMap map_;                  ///< the current node's bins (set by find_split, used by partition)
    Bin bins_[2][3][kMaxBins];                    ///< [set][axis][bin]: two sets, see find_split
};

}  // namespace

std::unique_ptr<Splitter> make_binned_sah_splitter(PrimRefs refs, int bins, SahCostModel model) {
    return std::make_unique<BinnedSahSplitter>(std::move(refs), bins, model);
}

}  // namespace accelviz::bvh_detail
