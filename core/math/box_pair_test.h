#pragma once
/// The widened slab test of box_test.h on a binary BVH node's two children at once.
/// The lecture's algorithm 2 tests both children's boxes at every interior node, and
/// the two sit next to each other in one cache line (bvh.h: 32 bytes each, lo.x lo.y
/// lo.z hi.x hi.y hi.z first count). With AVX2 one instruction sequence computes all
/// twelve plane distances: per child, a lane permutation picks the three near planes
/// and the three far planes (by the ray's direction signs, as near_plane/far_plane in
/// BoxTestRay), then one subtraction, one product and a max/min reduction per end give
/// both intervals. The binary tree is the lecture's; only its box test uses the
/// hardware's width, half the instructions of two scalar tests.
///
/// Exactness: each distance is (plane - o) · scale with the scalar test's operands,
/// one IEEE operation per lane, and the reduction is max / min written as
/// "a > b ? a : b" / "a < b ? a : b" (MAXPS / MINPS) starting from [t_min, t_max]
/// (or ±inf for rays that may hit behind their origin). Taking the maximum with
/// t_min first turns a NaN distance (0 · inf: the origin on a plane of a ±0 axis) into
/// t_min, so it never narrows the interval, as in widened_slab_test; the reduction
/// takes x against y, then z, keeping the earlier on a tie as the scalar loop does. So
/// both intervals equal the scalar test's bit for bit, box by box (a zero's sign
/// included, which the events show); the tests hold them to it. Without AVX2 the pair
/// is two scalar tests (scalar_slab_test_pair, which the tests check too).

#include <array>

#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "core/math/box_test.h"

namespace accelviz {

/// What the pair test needs of a ray, computed once per ray from its BoxTestRay.
template <bool kMayStartBehind>
struct BoxPairTestRay {
#if !defined(__AVX2__)
    const BoxTestRay* scalar;  ///< the ray the two scalar tests take
#else
    __m256i planes;      ///< per child: lanes 0-3 its near planes x, y, z, z; lanes 4-7 its far planes
    __m256 origin;       ///< o.x o.y o.z o.z, twice
    __m256 near_scale;   ///< what the near planes' distances are scaled by (x y z z, twice)
    __m256 far_scale;    ///< the same for the far planes
#endif

    [[gnu::always_inline]] explicit BoxPairTestRay(const BoxTestRay& ray) {
#if !defined(__AVX2__)
        scalar = &ray;
#else
        const Vec3& ns = kMayStartBehind ? ray.dir_inv : ray.near_dir_inv;
        const Vec3& fs = kMayStartBehind ? ray.dir_inv : ray.far_dir_inv;
        planes = _mm256_setr_epi32(ray.near_plane[0], ray.near_plane[1], ray.near_plane[2], ray.near_plane[2],
                                   ray.far_plane[0], ray.far_plane[1], ray.far_plane[2], ray.far_plane[2]);
        origin = _mm256_setr_ps(ray.origin.x, ray.origin.y, ray.origin.z, ray.origin.z, ray.origin.x, ray.origin.y,
                                ray.origin.z, ray.origin.z);
        near_scale = _mm256_setr_ps(ns.x, ns.y, ns.z, ns.z, ns.x, ns.y, ns.z, ns.z);
        far_scale = _mm256_setr_ps(fs.x, fs.y, fs.z, fs.z, fs.x, fs.y, fs.z, fs.z);
#endif
    }
};

/// Two boxes' intervals, and which of them the walk keeps.
struct SlabPair {
    std::array<SlabResult, 2> boxes;
    /// Bit i: box i's interval is not empty (t_enter <= t_exit) and begins no later
    /// than the limit the walk gave (the closest hit so far).
    uint32_t kept = 0;
};

/// Bit 0 / 1: box 0 / 1 is kept (see SlabPair::kept).
[[gnu::always_inline]] inline uint32_t kept_boxes(const std::array<SlabResult, 2>& boxes, float limit) {
    uint32_t kept = 0;
    for (uint32_t i = 0; i < 2; ++i)
        kept |= uint32_t(boxes[i].t_enter <= boxes[i].t_exit && boxes[i].t_enter <= limit) << i;
    return kept;
}

/// The pair as two scalar tests: what widened_slab_test_pair computes without AVX2.
template <bool kMayStartBehind>
[[gnu::always_inline]] inline SlabPair scalar_slab_test_pair(const Aabb& a, const Aabb& b, const BoxTestRay& ray,
                                                             float t_min, float t_max, float limit) {
    SlabPair r;
    r.boxes = {widened_slab_test<kMayStartBehind>(a, ray, t_min, t_max),
               widened_slab_test<kMayStartBehind>(b, ray, t_min, t_max)};
    r.kept = kept_boxes(r.boxes, limit);
    return r;
}

/// widened_slab_test on boxes `a` and `b`, and which of them the ray enters no later
/// than `limit`. Each box must be the first six of eight floats that start a 32-byte
/// record (a BVH node: its box, then two 32-bit words the test ignores): AVX2 loads
/// all eight.
template <bool kMayStartBehind>
[[gnu::always_inline]] inline SlabPair widened_slab_test_pair(const Aabb& a, const Aabb& b,
                                                              const BoxPairTestRay<kMayStartBehind>& ray, float t_min,
                                                              float t_max, float limit) {
#if defined(__AVX2__)
    // Lanes 0-3: a's near planes (x y z z), 4-7: a's far planes; the same for b.
    const __m256 pa = _mm256_permutevar8x32_ps(_mm256_loadu_ps(&a.lo.x), ray.planes);
    const __m256 pb = _mm256_permutevar8x32_ps(_mm256_loadu_ps(&b.lo.x), ray.planes);
    const __m256 near = _mm256_permute2f128_ps(pa, pb, 0x20);  // a's near planes | b's near planes
    const __m256 far = _mm256_permute2f128_ps(pa, pb, 0x31);   // a's far planes | b's far planes
    const float start = kMayStartBehind ? -kInfinity : t_min, end = kMayStartBehind ? kInfinity : t_max;
    __m256 enter = _mm256_max_ps(_mm256_mul_ps(_mm256_sub_ps(near, ray.origin), ray.near_scale), _mm256_set1_ps(start));
    __m256 exit = _mm256_min_ps(_mm256_mul_ps(_mm256_sub_ps(far, ray.origin), ray.far_scale), _mm256_set1_ps(end));
    // x against y, then that against z, the earlier axis kept on a tie (MAXPS returns
    // its second operand then), as the scalar loop keeps it: so even a zero's sign is
    // the scalar test's.
    enter = _mm256_max_ps(_mm256_permute_ps(enter, 0xb1), enter);  // lane 0: y vs x (lanes 1 0 3 2)
    exit = _mm256_min_ps(_mm256_permute_ps(exit, 0xb1), exit);
    enter = _mm256_max_ps(_mm256_permute_ps(enter, 0x4e), enter);  // lane 0: z vs (x, y) (lanes 2 3 0 1)
    exit = _mm256_min_ps(_mm256_permute_ps(exit, 0x4e), exit);
    SlabPair r;
    r.boxes = {SlabResult{_mm256_cvtss_f32(enter), _mm256_cvtss_f32(exit)},
               SlabResult{_mm_cvtss_f32(_mm256_extractf128_ps(enter, 1)), _mm_cvtss_f32(_mm256_extractf128_ps(exit, 1))}};
    if constexpr (kMayStartBehind) {
        for (SlabResult& box : r.boxes) box = widen_and_clip(box, t_min, t_max);
        r.kept = kept_boxes(r.boxes, limit);
    } else {
        // Both boxes' two comparisons in one: lanes 0 (a) and 4 (b).
        const __m256 fits = _mm256_and_ps(_mm256_cmp_ps(enter, exit, _CMP_LE_OQ),
                                          _mm256_cmp_ps(enter, _mm256_set1_ps(limit), _CMP_LE_OQ));
        const uint32_t mask = uint32_t(_mm256_movemask_ps(fits));
        r.kept = (mask & 1u) | (mask >> 3 & 2u);
    }
    return r;
#else
    return scalar_slab_test_pair<kMayStartBehind>(a, b, *ray.scalar, t_min, t_max, limit);
#endif
}

}  // namespace accelviz
