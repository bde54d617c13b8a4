#include "core/accel/bvh_build.h"

#include <algorithm>
#include <bit>
#include <chrono>
#include <cstddef>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "core/accel/sah.h"
#include "core/util/prefetch.h"

namespace accelviz {
namespace {

// ---------------------------------------------------------------------------
// [SECTION] What the builders work on
// ---------------------------------------------------------------------------

#if defined(__SSE2__)
/// Four floats from a 16-byte aligned address with the fourth replaced by 0 (a bitwise
/// AND, no arithmetic). The builder keeps each triangle's id in the four bytes after
/// its centroid, and read as a float an id below 2^23 is a subnormal number: a CPU
/// computes with subnormals on a slow path (microcode assists), and arithmetic on the
/// raw four floats would take it for every triangle at every level (docs/performance.md).
inline __m128 load_xyz(const float* p) {
    return _mm_and_ps(_mm_load_ps(p), _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)));
}
#endif

/// A box as two rows of four floats (x, y, z, unused), 16-byte aligned: growing one
/// box by another is then one 4-wide min and one 4-wide max (SSE where available;
/// the compiler does not vectorize the plain loop by itself). The builders' inner
/// loops grow boxes millions of times.
struct alignas(16) Box4 {
    float lo[4] = {kInfinity, kInfinity, kInfinity, kInfinity};
    float hi[4] = {-kInfinity, -kInfinity, -kInfinity, -kInfinity};

    Box4() = default;
    explicit Box4(const Aabb& b) : lo{b.lo.x, b.lo.y, b.lo.z, 0}, hi{b.hi.x, b.hi.y, b.hi.z, 0} {}
    void grow(const Box4& b) {
#if defined(__SSE__)
        _mm_store_ps(lo, _mm_min_ps(_mm_load_ps(lo), _mm_load_ps(b.lo)));
        _mm_store_ps(hi, _mm_max_ps(_mm_load_ps(hi), _mm_load_ps(b.hi)));
#else
        for (int i = 0; i < 4; ++i) {
            lo[i] = std::min(lo[i], b.lo[i]);
            hi[i] = std::max(hi[i], b.hi[i]);
        }
#endif
    }
    /// grow(b) if `yes`, else nothing; without a branch where SSE4.1 has a blend.
    void grow_if(bool yes, const Box4& b) {
#if defined(__SSE4_1__)
        grow_by_if(yes, _mm_load_ps(b.lo), _mm_load_ps(b.hi));
#else
        if (yes) grow_by(b.lo, b.hi);
#endif
    }
    /// The same for a point given as three floats at a 16-byte aligned address (the
    /// fourth float there is not part of the point: see load_xyz).
    void grow_point_if(bool yes, const float* p) {
#if defined(__SSE4_1__)
        const __m128 point = load_xyz(p);
        grow_by_if(yes, point, point);
#else
        if (yes) grow_by(p, p);
#endif
    }
    Aabb aabb() const { return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}}; }

    /// Aabb::area(), the same arithmetic in the same order (so the same float).
    float area() const {
#if defined(__SSE__)
        const __m128 l = _mm_load_ps(lo), h = _mm_load_ps(hi);
        if ((_mm_movemask_ps(_mm_cmple_ps(l, h)) & 7) != 7) return 0.0f;  // empty (or NaN)
        const __m128 e = _mm_sub_ps(h, l);                                  // ex ey ez
        const __m128 p = _mm_mul_ps(e, _mm_shuffle_ps(e, e, _MM_SHUFFLE(3, 0, 2, 1)));  // ex·ey ey·ez ez·ex
        const float sum = (_mm_cvtss_f32(p) + _mm_cvtss_f32(_mm_shuffle_ps(p, p, 1))) + _mm_cvtss_f32(_mm_shuffle_ps(p, p, 2));
        return 2.0f * sum;
#else
        if (!(lo[0] <= hi[0] && lo[1] <= hi[1] && lo[2] <= hi[2])) return 0.0f;  // empty
        const float ex = hi[0] - lo[0], ey = hi[1] - lo[1], ez = hi[2] - lo[2];
        return 2.0f * (ex * ey + ey * ez + ez * ex);
#endif
    }

private:
#if defined(__SSE4_1__)
    /// Grows to take in the box [low, high] if `yes`, by a mask instead of a branch.
    void grow_by_if(bool yes, __m128 low, __m128 high) {
        const __m128 mask = _mm_castsi128_ps(_mm_set1_epi32(-int(yes)));
        const __m128 l = _mm_load_ps(lo), h = _mm_load_ps(hi);
        _mm_store_ps(lo, _mm_blendv_ps(l, _mm_min_ps(l, low), mask));
        _mm_store_ps(hi, _mm_blendv_ps(h, _mm_max_ps(h, high), mask));
    }
#else
    /// Grows to take in the box [low, high] (x, y, z of three floats each).
    void grow_by(const float* low, const float* high) {
        for (int i = 0; i < 3; ++i) {
            lo[i] = std::min(lo[i], low[i]);
            hi[i] = std::max(hi[i], high[i]);
        }
    }
#endif
};

/// A triangle as the builder sees it: its box, its centroid and its id. 48 bytes,
/// so the partitions move small, contiguous records instead of chasing ids into the mesh.
struct PrimRef {
    Box4 box;
    Vec3 center;  ///< the triangle's centroid (p0 + p1 + p2) / 3: what the splits divide
    uint32_t id = 0;  ///< right after the centroid: a four-float load of it must mask this off (load_xyz)

    Vec3 centroid() const { return center; }
};
static_assert(offsetof(PrimRef, center) % 16 == 0, "the centroid is read as four aligned floats (with the id: see load_xyz)");
using PrimRefs = std::vector<PrimRef, LargeArrayAllocator<PrimRef>>;

/// The lecture splits by "the position of the primitive's centroid" (重心): the
/// mean of the three corners, summed in corner order.
PrimRef make_prim_ref(Vec3 p0, Vec3 p1, Vec3 p2, uint32_t id) {
    Aabb box;
    for (Vec3 p : {p0, p1, p2}) box.grow(p);  // as Mesh::triangle_bounds
    return {Box4(box), (p0 + p1 + p2) / 3.0f, id};
}

/// A node's triangles during the build: positions [begin, end) of the builder's order.
struct Range {
    uint32_t begin, end;
    uint32_t count() const { return end - begin; }
};

/// The split a builder proposes for a range.
struct SplitChoice {
    bool found = false;            ///< false: no plane separates the centroids
    int axis = -1;
    float position = 0;            ///< the plane, as a centroid coordinate on `axis`
    uint32_t left_count = 0;
    float cost = kInfinity;        ///< SAH builders: C_split of this choice
    uint32_t index = 0;            ///< sah-binned: first bin on the right; sah-sweep: = left_count
    bool median_fallback = false;  ///< midpoint only: the middle plane left one side empty
};

/// The two children's boxes, when a partition computes them on the way (saves a pass).
struct ChildBounds {
    bool filled = false;
    Aabb bounds[2], centroid_bounds[2];  ///< [0] left, [1] right
};

/// One builder's way of choosing and applying splits. The driver (build_bvh)
/// owns the decisions (leaf or split, fallbacks, depth budget); a splitter only
/// measures ranges, proposes a split, and reorders its triangles.
class Splitter {
public:
    virtual ~Splitter() = default;
    virtual bool uses_sah() const = 0;
    /// Union of the range's triangle boxes, and the box of their centroids.
    virtual void measure(Range range, Aabb& bounds, Aabb& centroid_bounds) const = 0;
    /// The builder's split of the range. `step`, when not null, receives the candidates.
    virtual SplitChoice find_split(Range range, const Aabb& bounds, const Aabb& centroid_bounds, BuildStep* step) = 0;
    /// Reorders the range so that the choice's left side comes first; returns the first
    /// right position. May fill `children` (then the driver need not measure them).
    virtual uint32_t partition(Range range, const SplitChoice& choice, ChildBounds& children) = 0;
    /// The fallback: the first half of the range (by position) goes left. Returns begin + count/2.
    virtual uint32_t partition_in_half(Range range) = 0;
    /// The triangle id at position k once the build is done.
    virtual uint32_t prim_id(uint32_t k) const = 0;
};

void measure_refs(const PrimRef* refs, Range range, Aabb& bounds, Aabb& centroid_bounds) {
    Box4 box;
    centroid_bounds = {};
    for (uint32_t k = range.begin; k < range.end; ++k) {
        box.grow(refs[k].box);
        centroid_bounds.grow(refs[k].centroid());
    }
    bounds = box.aabb();
}

/// Longest axis of the centroid bounds, or -1 if they are a single point (all centroids equal).
int longest_axis(const Aabb& centroid_bounds) {
    const Vec3 extent = centroid_bounds.extent();
    const int axis = max_axis(extent);
    return extent[axis] > 0.0f ? axis : -1;
}

/// Splitters that reorder one array of PrimRefs in place (all but the sweep).
class InPlaceSplitter : public Splitter {
public:
    explicit InPlaceSplitter(PrimRefs refs) : refs_(std::move(refs)) {}
    void measure(Range range, Aabb& bounds, Aabb& centroid_bounds) const override {
        measure_refs(refs_.data(), range, bounds, centroid_bounds);
    }
    uint32_t partition_in_half(Range range) override { return range.begin + range.count() / 2; }
    uint32_t prim_id(uint32_t k) const override { return refs_[k].id; }

protected:
    /// Puts the median (by centroid on `axis`, ties by id) at begin + count/2, smaller ones before it.
    float nth_element_median(Range range, int axis) {
        const uint32_t mid = range.begin + range.count() / 2;
        std::nth_element(refs_.begin() + range.begin, refs_.begin() + mid, refs_.begin() + range.end,
                         [axis](const PrimRef& a, const PrimRef& b) {
                             const float ca = a.centroid()[axis], cb = b.centroid()[axis];
                             return ca < cb || (ca == cb && a.id < b.id);
                         });
        return refs_[mid].centroid()[axis];
    }

    PrimRefs refs_;
};

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
        // bins, merged after.
        uint64_t used[3] = {0, 0, 0};
        auto drop = [&](int set, const PrimRef& ref) {
            const BinIndices b = map(ref);
            for (int axis = 0; axis < 3; ++axis) {
                if (!usable[axis]) continue;
                Bin& bin = bins_[set][axis][b.index[axis]];
                bin.box.grow(ref.box);
                ++bin.count;
                used[axis] |= uint64_t(1) << b.index[axis];
            }
        };
        uint32_t k = range.begin;
        if (range.count() >= kTwoBinSets) {
            for (; k + 1 < range.end; k += 2) {
                drop(0, refs_[k]);
                drop(1, refs_[k + 1]);
            }
            for (int axis = 0; axis < 3; ++axis) {
                for (uint64_t m = used[axis]; m != 0; m &= m - 1) {
                    Bin& bin = bins_[0][axis][std::countr_zero(m)];
                    Bin& odd = bins_[1][axis][std::countr_zero(m)];
                    bin.box.grow(odd.box);
                    bin.count += odd.count;
                    odd = {};
                }
            }
        }
        for (; k < range.end; ++k) {
            drop(0, refs_[k]);
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

// ---------------------------------------------------------------------------
// [SECTION] The driver: one decision per node, explicit work stack
// ---------------------------------------------------------------------------

std::unique_ptr<Splitter> make_splitter(const BvhConfig& config, PrimRefs refs) {
    const SahCostModel model{config.cost_trav, config.cost_isect};
    switch (config.builder) {
        case BvhBuilder::Midpoint: return std::make_unique<MidpointSplitter>(std::move(refs));
        case BvhBuilder::Median: return std::make_unique<MedianSplitter>(std::move(refs));
        case BvhBuilder::SahSweep: return std::make_unique<SweepSahSplitter>(std::move(refs), model);
        case BvhBuilder::SahBinned: break;
    }
    return std::make_unique<BinnedSahSplitter>(std::move(refs), config.bins, model);
}

/// How many halvings turn `count` triangles into leaves of at most `max_leaf` (0 if it fits).
uint32_t levels_needed(uint32_t count, uint32_t max_leaf) {
    uint32_t levels = 0;
    for (; count > max_leaf; count = count - count / 2) ++levels;
    return levels;
}

bool is_leaf(BuildDecision d) {
    return d == BuildDecision::LeafFits || d == BuildDecision::LeafCheaper ||
           d == BuildDecision::LeafNoSeparatingPlane || d == BuildDecision::LeafDepthLimit;
}

bool splits_in_half(BuildDecision d) {
    return d == BuildDecision::SplitInHalfCentroidsEqual || d == BuildDecision::SplitInHalfDepthBudget;
}

/// Leaf or split, and which split (see BuildDecision). `choice` is filled when a split was searched.
/// Depth budget: every node satisfies depth + levels_needed(count) <= kBvhMaxDepth (true at the
/// root for any 32-bit count). A split by index keeps it; the builder's own split is taken
/// only if its larger child keeps it too. So no leaf is ever deeper than kBvhMaxDepth.
BuildDecision decide(Splitter& splitter, Range range, uint32_t depth, const Aabb& bounds, const Aabb& centroid_bounds,
                     const BvhConfig& config, const SahCostModel& model, SplitChoice& choice, BuildStep* step) {
    const uint32_t n = range.count();
    const bool fits = n <= uint32_t(config.max_leaf_size);
    if (n == 1 || (fits && !splitter.uses_sah())) return BuildDecision::LeafFits;

    choice = splitter.find_split(range, bounds, centroid_bounds, step);
    const uint32_t larger_child = std::max(choice.left_count, n - choice.left_count);
    const bool within_budget =
        choice.found && depth + 1 + levels_needed(larger_child, uint32_t(config.max_leaf_size)) <= kBvhMaxDepth;

    if (!splitter.uses_sah()) {
        if (!choice.found) return BuildDecision::SplitInHalfCentroidsEqual;
        if (!within_budget) return BuildDecision::SplitInHalfDepthBudget;
        return choice.median_fallback ? BuildDecision::SplitMedianFallback : BuildDecision::Split;
    }
    // SAH: split only if it is cheaper than the leaf, or if the leaf would not fit.
    if (choice.found && choice.cost < model.leaf_cost(n)) {
        if (within_budget) return BuildDecision::Split;
        return fits ? BuildDecision::LeafDepthLimit : BuildDecision::SplitInHalfDepthBudget;
    }
    if (fits) return choice.found ? BuildDecision::LeafCheaper : BuildDecision::LeafNoSeparatingPlane;
    if (!choice.found) return BuildDecision::SplitInHalfCentroidsEqual;
    return within_budget ? BuildDecision::SplitForcedBySize : BuildDecision::SplitInHalfDepthBudget;
}

/// Fills bvh.triangles in leaf order: triangles[k] = mesh.triangle(prim_ids[k]). The ids
/// jump around the mesh, so each triangle's index triple and corners are a cache miss of
/// their own; the loop asks for them some triangles ahead (the index triple first, its
/// corners once the triple has had time to arrive) so the misses overlap instead of
/// following each other.
void copy_triangles_in_leaf_order(const Mesh& mesh, Bvh& bvh) {
    constexpr size_t kTriplesAhead = 16, kCornersAhead = 8;
    const auto& ids = bvh.prim_ids;
    const size_t n = ids.size();
    bvh.triangles.reserve(n);
    for (size_t k = 0; k < n; ++k) {
        if (k + kTriplesAhead < n) prefetch(&mesh.indices[ids[k + kTriplesAhead]]);
        if (k + kCornersAhead < n) {
            for (uint32_t corner : mesh.indices[ids[k + kCornersAhead]]) prefetch(&mesh.positions[corner]);
        }
        bvh.triangles.push_back(mesh.triangle(ids[k]));
    }
}

/// Depths, leaf sizes and SAH cost of the tree, gathered as the build makes its nodes
/// (parents before children, left subtree first).
class TreeStats {
public:
    TreeStats(const SahCostModel& model, uint32_t max_leaf_size) : model_(model), max_leaf_size_(max_leaf_size) {}

    /// Every node, the root first: its share of the SAH cost (its hit probability times
    /// C_trav for an interior node, times count · C_isect for a leaf).
    void add_node(const Aabb& bounds, uint32_t depth, uint32_t leaf_count, BvhBuildStats& stats) {
        if (depth == 0) root_area_ = bounds.area();
        const double p = SahCostModel::hit_probability(bounds.area(), root_area_);
        if (leaf_count == 0) {
            sah_ += p * model_.cost_trav;
            return;
        }
        ++stats.leaves;
        depth_sum_ += depth;
        stats.max_depth = std::max(stats.max_depth, depth);
        if (stats.leaf_size_histogram.size() <= leaf_count) stats.leaf_size_histogram.resize(leaf_count + 1, 0);
        ++stats.leaf_size_histogram[leaf_count];
        if (leaf_count > max_leaf_size_) ++stats.leaves_over_limit;
        sah_ += p * leaf_count * model_.cost_isect;
    }
    /// Totals and memory, once the tree is complete.
    void finish(const Bvh& bvh, BvhBuildStats& stats) const {
        stats.nodes = uint32_t(bvh.nodes.size());
        stats.memory_bytes = bvh.nodes.size() * sizeof(BvhNode) + bvh.prim_ids.size() * sizeof(uint32_t) +
                             bvh.triangles.size() * sizeof(Triangle);
        if (stats.leaves == 0) return;
        stats.avg_leaf_depth = depth_sum_ / stats.leaves;
        stats.sah_cost = sah_;
    }

private:
    SahCostModel model_;
    uint32_t max_leaf_size_;
    float root_area_ = 0;
    double depth_sum_ = 0, sah_ = 0;
};

/// One sentence per unusual decision, so the stats say why the tree looks as it does.
void write_notes(const BvhConfig& config, BvhBuildStats& stats) {
    auto note = [&](BuildDecision d, const std::string& what) {
        if (const uint32_t n = stats.count(d)) stats.notes.push_back(std::to_string(n) + " " + what);
    };
    if (stats.triangles == 0) stats.notes.push_back("empty scene: the tree has no nodes and every ray misses");
    note(BuildDecision::SplitInHalfCentroidsEqual,
         "nodes split in half by index: all their triangles' centroids are equal, so no plane separates them");
    note(BuildDecision::LeafNoSeparatingPlane,
         "leaves made because all their triangles' centroids are equal (no plane separates them)");
    note(BuildDecision::SplitMedianFallback,
         "nodes split at the median: the middle of their centroid bounds rounded onto one end (bounds a few floats wide)");
    note(BuildDecision::SplitForcedBySize, "nodes split although a leaf was cheaper by the SAH: a leaf may hold at most " +
                                               std::to_string(config.max_leaf_size) + " triangles");
    note(BuildDecision::SplitInHalfDepthBudget,
         "nodes split in half by index: the builder's split could have made the tree deeper than " +
             std::to_string(kBvhMaxDepth) + " levels");
    note(BuildDecision::LeafDepthLimit,
         "leaves made because a split would have made the tree deeper than " + std::to_string(kBvhMaxDepth) + " levels");
    if (stats.leaves_over_limit)
        stats.notes.push_back(std::to_string(stats.leaves_over_limit) + " leaves larger than the limit of " +
                              std::to_string(config.max_leaf_size));
}

}  // namespace

Expected<Bvh> build_bvh(const Mesh& mesh, const BvhConfig& requested, BuildRecorder* recorder) {
    if (auto err = validate(requested)) return *err;
    const auto start = std::chrono::steady_clock::now();
    Bvh bvh;
    bvh.build_config = requested;
    const BvhConfig& config = bvh.build_config;
    const SahCostModel model{config.cost_trav, config.cost_isect};
    BvhBuildStats& stats = bvh.build_stats;
    const auto n = uint32_t(mesh.triangle_count());
    stats.triangles = n;

    TreeStats tree_stats(model, uint32_t(config.max_leaf_size));
    if (n > 0) {
        PrimRefs refs;
        refs.reserve(n);
        for (uint32_t i = 0; i < n; ++i) refs.push_back(make_prim_ref(mesh.vertex(i, 0), mesh.vertex(i, 1), mesh.vertex(i, 2), i));
        std::unique_ptr<Splitter> splitter = make_splitter(config, std::move(refs));

        bvh.nodes.reserve(2 * size_t(n) - 1);  // a binary tree with at most n leaves
        bvh.nodes.emplace_back();
        /// A node still to build; its boxes come along when the parent's partition measured them.
        struct Task {
            uint32_t node, begin, end, depth;
            bool measured = false;
            Aabb bounds, centroid_bounds;
        };
        // The left child goes straight on as the next task; the right one waits on the
        // stack: left subtrees are built (and laid out) first, depth first.
        std::vector<Task> work;
        std::optional<Task> left_next = Task{0, 0, n, 0, false, {}, {}};
        while (left_next || !work.empty()) {
            Task task;
            if (left_next) {
                task = *left_next;
                left_next.reset();
            } else {
                task = work.back();
                work.pop_back();
            }
            const Range range{task.begin, task.end};
            Aabb bounds = task.bounds, centroid_bounds = task.centroid_bounds;
            if (!task.measured) splitter->measure(range, bounds, centroid_bounds);
            bvh.nodes[task.node].bounds = bounds;

            std::optional<BuildStep> step;
            if (recorder) step.emplace();
            SplitChoice choice;
            const BuildDecision decision =
                decide(*splitter, range, task.depth, bounds, centroid_bounds, config, model, choice,
                       step && recorder->record_candidates ? &*step : nullptr);
            ++stats.decisions[size_t(decision)];

            if (is_leaf(decision)) {
                bvh.nodes[task.node].first = range.begin;
                bvh.nodes[task.node].count = range.count();
                tree_stats.add_node(bounds, task.depth, range.count(), stats);
            } else {
                tree_stats.add_node(bounds, task.depth, 0, stats);
                ChildBounds children;
                const uint32_t mid = splits_in_half(decision) ? splitter->partition_in_half(range)
                                                              : splitter->partition(range, choice, children);
                if (!children.filled) {
                    splitter->measure({range.begin, mid}, children.bounds[0], children.centroid_bounds[0]);
                    splitter->measure({mid, range.end}, children.bounds[1], children.centroid_bounds[1]);
                }
                const auto left = uint32_t(bvh.nodes.size());
                bvh.nodes.emplace_back();
                bvh.nodes.emplace_back();
                bvh.nodes[task.node].first = left;
                bvh.nodes[task.node].count = 0;
                work.push_back({left + 1, mid, range.end, task.depth + 1, true, children.bounds[1],
                                children.centroid_bounds[1]});
                left_next = Task{left, range.begin, mid, task.depth + 1, true, children.bounds[0],
                                 children.centroid_bounds[0]};
                if (step) {
                    step->split_cost = model.split_cost(bounds.area(), children.bounds[0].area(), mid - range.begin,
                                                        children.bounds[1].area(), range.end - mid);
                    step->left_count = mid - range.begin;
                    if (!splits_in_half(decision)) {
                        step->axis = choice.axis;
                        step->split_position = choice.position;
                    }
                }
            }
            if (step) {
                step->node = task.node;
                step->depth = task.depth;
                step->first = range.begin;
                step->count = range.count();
                step->bounds = bounds;
                step->centroid_bounds = centroid_bounds;
                step->decision = decision;
                step->leaf_cost = model.leaf_cost(range.count());
                recorder->steps.push_back(std::move(*step));
            }
        }
        // Leaf order: the triangles of each leaf next to each other, as the traversal reads them.
        bvh.prim_ids.resize(n);
        for (uint32_t k = 0; k < n; ++k) bvh.prim_ids[k] = splitter->prim_id(k);
        // The build records go before the leaf-order copy is made, so the two are never in
        // memory together (a lower peak).
        splitter.reset();
        copy_triangles_in_leaf_order(mesh, bvh);
    }

    tree_stats.finish(bvh, stats);
    write_notes(config, stats);
    stats.build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    return bvh;
}

}  // namespace accelviz
