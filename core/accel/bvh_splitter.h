#pragma once
/// What the BVH builders share, inside core/accel: the build records (PrimRef,
/// Box4), a node's range of them, the split a builder proposes, and the Splitter
/// interface that the driver, build_bvh() in bvh_build.cpp, calls. One builder per
/// file: bvh_split_heuristics.cpp (the lecture's midpoint and median heuristics),
/// bvh_split_binned_sah.cpp (binned SAH) and bvh_split_sweep_sah.cpp (full SAH sweep).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#if defined(__SSE__)
#include <immintrin.h>
#endif

#include "core/accel/bvh_build.h"
#include "core/accel/sah.h"
#include "core/util/large_array.h"

namespace accelviz::bvh_detail {

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
/// Made at their final size (make_prefaulted) and filled in parallel.
using PrimRefs = std::vector<PrimRef, LargeArrayAllocator<PrimRef>>;

/// The lecture splits by "the position of the primitive's centroid" (重心): the
/// mean of the three corners, summed in corner order.
inline PrimRef make_prim_ref(Vec3 p0, Vec3 p1, Vec3 p2, uint32_t id) {
    return {Box4(triangle_box(p0, p1, p2)), (p0 + p1 + p2) / 3.0f, id};
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
///
/// A splitter works only inside the range it is given, so two splitters may work on
/// disjoint ranges of the same triangle records at once: fork() makes the second one
/// (same records, its own scratch), which is how the driver builds two subtrees in
/// parallel.
class Splitter {
public:
    virtual ~Splitter() = default;
    /// A splitter over the same triangle records with scratch of its own.
    virtual std::unique_ptr<Splitter> fork() const = 0;
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

inline void measure_refs(const PrimRef* refs, Range range, Aabb& bounds, Aabb& centroid_bounds) {
    Box4 box;
    centroid_bounds = {};
    for (uint32_t k = range.begin; k < range.end; ++k) {
        box.grow(refs[k].box);
        centroid_bounds.grow(refs[k].centroid());
    }
    bounds = box.aabb();
}

/// Longest axis of the centroid bounds, or -1 if they are a single point (all centroids equal).
inline int longest_axis(const Aabb& centroid_bounds) {
    const Vec3 extent = centroid_bounds.extent();
    const int axis = max_axis(extent);
    return extent[axis] > 0.0f ? axis : -1;
}

/// Splitters that reorder one array of PrimRefs in place (all but the sweep). Forks
/// share the array.
class InPlaceSplitter : public Splitter {
public:
    explicit InPlaceSplitter(PrimRefs refs) : storage_(std::make_shared<PrimRefs>(std::move(refs))), refs_(*storage_) {}
    InPlaceSplitter(const InPlaceSplitter& other) : Splitter(other), storage_(other.storage_), refs_(*storage_) {}
    InPlaceSplitter& operator=(const InPlaceSplitter&) = delete;
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

private:
    std::shared_ptr<PrimRefs> storage_;  ///< shared by the forks

protected:
    PrimRefs& refs_;
};

// ---------------------------------------------------------------------------
// [SECTION] The builders (one file each)
// ---------------------------------------------------------------------------

/// Heuristic 1: the longest centroid axis cut at its middle (bvh_split_heuristics.cpp).
std::unique_ptr<Splitter> make_midpoint_splitter(PrimRefs refs);
/// Heuristic 2: the longest centroid axis cut at the median triangle (bvh_split_heuristics.cpp).
std::unique_ptr<Splitter> make_median_splitter(PrimRefs refs);
/// Binned SAH with `bins` buckets per axis (bvh_split_binned_sah.cpp).
std::unique_ptr<Splitter> make_binned_sah_splitter(PrimRefs refs, int bins, SahCostModel model);
/// Full SAH sweep over every centroid on every axis (bvh_split_sweep_sah.cpp).
std::unique_ptr<Splitter> make_sweep_sah_splitter(PrimRefs refs, SahCostModel model);

}  // namespace accelviz::bvh_detail
