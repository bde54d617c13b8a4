#pragma once
/// The widened slab test of box_test.h on W boxes at once: the lesson of the wide
/// BVH ("BVHs suit parallel hardware"): one instruction sequence tests all of a
/// node's children. The boxes are stored as structure of arrays (lo.x of every
/// child, then lo.y, ...), so each step of the slab test is one SIMD instruction
/// over all W boxes.
///
/// Three implementations of the same few lane operations: SSE (4 lanes), AVX
/// (8 lanes) and a plain loop over W floats. Each operation is defined to give
/// exactly what the scalar test computes (the same subtraction and product per
/// lane, and max/min written as "a > b ? a : b" / "a < b ? a : b", which is what
/// MAXPS/MINPS do, NaN and ±0 included), so every implementation returns
/// bit-identical intervals to widened_slab_test() box by box: the wide BVH's
/// answers stay exactly brute force's, and the tests compare the SIMD lanes with
/// the loop. The wide BVH's leaves test four triangles with the same lanes
/// (geometry/triangle_lanes.h: its additions, divisions and equality too).

#include <array>
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

#include "core/math/box_test.h"

namespace accelviz {

/// W floats as a plain array: the fallback, and the reference the tests hold the
/// SIMD lanes to.
template <int W>
struct ScalarLanes {
    static constexpr int kWidth = W;
    using Four = ScalarLanes<4>;  ///< the same kind of lanes, four wide (a leaf's triangle lanes)
    std::array<float, W> v;

    static ScalarLanes load(const float* p) {
        ScalarLanes r;
        for (int i = 0; i < W; ++i) r.v[i] = p[i];
        return r;
    }
    static ScalarLanes load_unaligned(const float* p) { return load(p); }
    static ScalarLanes splat(float x) {
        ScalarLanes r;
        r.v.fill(x);
        return r;
    }
    void store(float* p) const {
        for (int i = 0; i < W; ++i) p[i] = v[i];
    }
    template <class Op>
    static ScalarLanes map(const ScalarLanes& a, const ScalarLanes& b, Op op) {
        ScalarLanes r;
        for (int i = 0; i < W; ++i) r.v[i] = op(a.v[i], b.v[i]);
        return r;
    }
    friend ScalarLanes operator-(const ScalarLanes& a, const ScalarLanes& b) {
        return map(a, b, [](float x, float y) { return x - y; });
    }
    friend ScalarLanes operator*(const ScalarLanes& a, const ScalarLanes& b) {
        return map(a, b, [](float x, float y) { return x * y; });
    }
    friend ScalarLanes operator+(const ScalarLanes& a, const ScalarLanes& b) {
        return map(a, b, [](float x, float y) { return x + y; });
    }
    friend ScalarLanes operator/(const ScalarLanes& a, const ScalarLanes& b) {
        return map(a, b, [](float x, float y) { return x / y; });
    }
    /// a > b ? a : b per lane (b when either is NaN).
    static ScalarLanes max(const ScalarLanes& a, const ScalarLanes& b) {
        return map(a, b, [](float x, float y) { return x > y ? x : y; });
    }
    /// a < b ? a : b per lane (b when either is NaN).
    static ScalarLanes min(const ScalarLanes& a, const ScalarLanes& b) {
        return map(a, b, [](float x, float y) { return x < y ? x : y; });
    }
    /// Bit i set where a[i] <= b[i] (false for NaN).
    static uint32_t less_equal(const ScalarLanes& a, const ScalarLanes& b) {
        uint32_t m = 0;
        for (int i = 0; i < W; ++i) m |= uint32_t(a.v[i] <= b.v[i]) << i;
        return m;
    }
    /// Bit i set where a[i] == b[i] (false for NaN).
    static uint32_t equal(const ScalarLanes& a, const ScalarLanes& b) {
        uint32_t m = 0;
        for (int i = 0; i < W; ++i) m |= uint32_t(a.v[i] == b.v[i]) << i;
        return m;
    }
    /// x[i] > 0 ? if_positive : otherwise, per lane.
    static ScalarLanes select_positive(const ScalarLanes& x, float if_positive, float otherwise) {
        ScalarLanes r;
        for (int i = 0; i < W; ++i) r.v[i] = x.v[i] > 0.0f ? if_positive : otherwise;
        return r;
    }
};

#if defined(__SSE2__)
/// Four floats in an SSE register.
struct SseLanes {
    static constexpr int kWidth = 4;
    using Four = SseLanes;
    __m128 v;

    static SseLanes load(const float* p) { return {_mm_load_ps(p)}; }
    static SseLanes load_unaligned(const float* p) { return {_mm_loadu_ps(p)}; }
    static SseLanes splat(float x) { return {_mm_set1_ps(x)}; }
    void store(float* p) const { _mm_storeu_ps(p, v); }
    friend SseLanes operator-(SseLanes a, SseLanes b) { return {_mm_sub_ps(a.v, b.v)}; }
    friend SseLanes operator*(SseLanes a, SseLanes b) { return {_mm_mul_ps(a.v, b.v)}; }
    friend SseLanes operator+(SseLanes a, SseLanes b) { return {_mm_add_ps(a.v, b.v)}; }
    friend SseLanes operator/(SseLanes a, SseLanes b) { return {_mm_div_ps(a.v, b.v)}; }
    static SseLanes max(SseLanes a, SseLanes b) { return {_mm_max_ps(a.v, b.v)}; }  // MAXPS: a > b ? a : b
    static SseLanes min(SseLanes a, SseLanes b) { return {_mm_min_ps(a.v, b.v)}; }  // MINPS: a < b ? a : b
    static uint32_t less_equal(SseLanes a, SseLanes b) { return uint32_t(_mm_movemask_ps(_mm_cmple_ps(a.v, b.v))); }
    static uint32_t equal(SseLanes a, SseLanes b) { return uint32_t(_mm_movemask_ps(_mm_cmpeq_ps(a.v, b.v))); }
    static SseLanes select_positive(SseLanes x, float if_positive, float otherwise) {
        const __m128 positive = _mm_cmpgt_ps(x.v, _mm_setzero_ps());
        return {_mm_or_ps(_mm_and_ps(positive, _mm_set1_ps(if_positive)),
                          _mm_andnot_ps(positive, _mm_set1_ps(otherwise)))};
    }
};
#endif

#if defined(__AVX__)
/// Eight floats in an AVX register.
struct AvxLanes {
    static constexpr int kWidth = 8;
    using Four = SseLanes;
    __m256 v;

    static AvxLanes load(const float* p) { return {_mm256_load_ps(p)}; }
    static AvxLanes load_unaligned(const float* p) { return {_mm256_loadu_ps(p)}; }
    static AvxLanes splat(float x) { return {_mm256_set1_ps(x)}; }
    void store(float* p) const { _mm256_storeu_ps(p, v); }
    friend AvxLanes operator-(AvxLanes a, AvxLanes b) { return {_mm256_sub_ps(a.v, b.v)}; }
    friend AvxLanes operator*(AvxLanes a, AvxLanes b) { return {_mm256_mul_ps(a.v, b.v)}; }
    static AvxLanes max(AvxLanes a, AvxLanes b) { return {_mm256_max_ps(a.v, b.v)}; }  // a > b ? a : b
    static AvxLanes min(AvxLanes a, AvxLanes b) { return {_mm256_min_ps(a.v, b.v)}; }  // a < b ? a : b
    static uint32_t less_equal(AvxLanes a, AvxLanes b) {
        return uint32_t(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)));
    }
    static AvxLanes select_positive(AvxLanes x, float if_positive, float otherwise) {
        const __m256 positive = _mm256_cmp_ps(x.v, _mm256_setzero_ps(), _CMP_GT_OQ);
        return {_mm256_blendv_ps(_mm256_set1_ps(otherwise), _mm256_set1_ps(if_positive), positive)};
    }
};
#endif

/// The fastest lanes this build has for W boxes (-march=native picks them for this CPU).
template <int W>
struct FastLanesFor {
    using type = ScalarLanes<W>;
};
#if defined(__SSE2__)
template <>
struct FastLanesFor<4> {
    using type = SseLanes;
};
#endif
#if defined(__AVX__)
template <>
struct FastLanesFor<8> {
    using type = AvxLanes;
};
#endif
template <int W>
using FastLanes = typename FastLanesFor<W>::type;

/// W boxes as structure of arrays: lo.x of each box, lo.y, lo.z, hi.x, hi.y, hi.z.
/// Plane p (0..5: lo.x lo.y lo.z hi.x hi.y hi.z, the order of BoxTestRay's
/// near_plane/far_plane) of box i is planes[p][i].
template <int W>
struct BoxLanes {
    alignas(W * sizeof(float)) float planes[6][W];

    void set(int i, const Aabb& box) {
        for (int p = 0; p < 6; ++p) planes[p][i] = (&box.lo.x)[p];
    }
    Aabb get(int i) const {
        return {{planes[0][i], planes[1][i], planes[2][i]}, {planes[3][i], planes[4][i], planes[5][i]}};
    }
};

/// widened_slab_test() of all W boxes: their intervals, clipped to [t_min, t_max],
/// in t_enter[] and t_exit[], and the bit mask of boxes the ray enters (t_enter <=
/// t_exit). Box by box the same operations in the same order as the scalar test.
template <class Lanes, bool kMayStartBehind, int W>
[[gnu::always_inline]] inline uint32_t widened_slab_test_lanes(const BoxLanes<W>& boxes, const BoxTestRay& ray,
                                                               float t_min, float t_max, float* t_enter,
                                                               float* t_exit) {
    static_assert(Lanes::kWidth == W);
    const Vec3& near_scale = kMayStartBehind ? ray.dir_inv : ray.near_dir_inv;
    const Vec3& far_scale = kMayStartBehind ? ray.dir_inv : ray.far_dir_inv;
    Lanes enter = Lanes::splat(kMayStartBehind ? -kInfinity : t_min);
    Lanes exit = Lanes::splat(kMayStartBehind ? kInfinity : t_max);
    for (int axis = 0; axis < 3; ++axis) {
        const Lanes origin = Lanes::splat(ray.origin[axis]);
        const Lanes t_near =
            (Lanes::load(boxes.planes[ray.near_plane[axis]]) - origin) * Lanes::splat(near_scale[axis]);
        const Lanes t_far = (Lanes::load(boxes.planes[ray.far_plane[axis]]) - origin) * Lanes::splat(far_scale[axis]);
        enter = Lanes::max(t_near, enter);
        exit = Lanes::min(t_far, exit);
    }
    if constexpr (kMayStartBehind) {  // as widened_slab_test: each end outwards by its sign, then clip
        enter = enter * Lanes::select_positive(enter, 1.0f - kBoxTestMargin, 1.0f + kBoxTestMargin);
        exit = exit * Lanes::select_positive(exit, 1.0f + kBoxTestMargin, 1.0f - kBoxTestMargin);
        enter = Lanes::max(enter, Lanes::splat(t_min));
        exit = Lanes::min(exit, Lanes::splat(t_max));
    }
    enter.store(t_enter);
    exit.store(t_exit);
    return Lanes::less_equal(enter, exit);
}

}  // namespace accelviz
