#pragma once
/// The BVH's ray–box test: the lecture's slab test (core/math/aabb.h), widened
/// by a few units in the last place so that it never rejects a box around a
/// triangle that Möller–Trumbore accepts. The ray–triangle test uses the same
/// widened test on each triangle's own box (intersect_triangle, core/geometry/triangle.h).
///
/// Why widen? The slab test and Möller–Trumbore round differently. A ray aimed
/// exactly at a vertex that is also a box corner can come out "just outside the
/// box" by the slab test's rounding and "just inside the triangle" (u = 1e-7,
/// v = 0) by Möller–Trumbore's. Brute force tests every triangle, so it finds
/// that hit; a BVH with the exact slab test would skip the box and miss it. In
/// the same way a triangle lying in a box face can have a Möller–Trumbore t a
/// few ulps smaller than the box's entry distance, so comparing t_enter with
/// the closest hit must leave the same slack.
///
/// The fix follows Ize, "Robust BVH Ray Traversal" (JCGT 2013): compute the slab
/// interval as usual (NaN-safe, exact for ±0 direction components) but move
/// t_enter down and t_exit up by the relative margin kBoxTestMargin before
/// clipping it to the ray's [t_min, t_max]. Ize's margin 2γ₃ covers the slab
/// test's own rounding; ours is a few times larger to cover Möller–Trumbore's too.
/// The cost of a wider box is only an occasional extra node visit: the answer
/// is decided by the triangle tests, exactly as in brute force.
///
/// No margin alone covers every case: Möller–Trumbore's error grows as 1/det, so
/// for a sliver triangle hit exactly at a vertex it can report t well outside the
/// triangle's own box (up to 4% at the collapsed tip of the teapot's lid), or a hit
/// on a ray that passes beside the box. The triangle test's own-box rule closes
/// that gap: every hit it reports lies in its triangle's widened box, hence in
/// every node box above it, since this test's interval only grows with the box.

#include "core/math/aabb.h"

namespace accelviz {

/// Relative slack of the BVH box test: 2^-16 (about 1.5e-5).
/// Measured: 2^-20 still let a few of 100,000 test rays through the sliver
/// triangles at the tip of the teapot's lid (builtin:stadium) differ from brute
/// force; 2^-16 passes every test scene. It widens a box seen from distance t by
/// 1.5e-5 t, a negligible number of extra visits.
inline constexpr float kBoxTestMargin = 0x1.0p-16f;

/// What the box test needs of a ray, computed once per ray: the origin, 1/dir
/// (±inf for ±0 components), the same scaled for the near and for the far planes,
/// and per axis whether the ray runs towards -inf (then it meets the box's hi plane first).
struct BoxTestRay {
    Vec3 origin;
    Vec3 dir_inv;       ///< 1/d, as RayPrecomp
    Vec3 near_dir_inv;  ///< 1/d · (1 - margin): near-plane distances come out a little smaller
    Vec3 far_dir_inv;   ///< 1/d · (1 + margin): far-plane distances come out a little larger
    /// Per axis, where the near and the far plane sit among a box's six floats
    /// (lo.x lo.y lo.z hi.x hi.y hi.z): axis, or axis + 3 when the ray runs towards
    /// -inf on that axis. Picking a plane is then a load, not a branch.
    int near_plane[3];
    int far_plane[3];

    /// (Written out, not made through RayPrecomp: that detour made the BVH's walk,
    /// which builds this from a Ray, markedly slower on rays that miss; figures in
    /// docs/performance.md.)
    [[gnu::always_inline]] explicit BoxTestRay(const Ray& ray)
        : origin(ray.origin), dir_inv(1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z),
          near_dir_inv(dir_inv * (1.0f - kBoxTestMargin)), far_dir_inv(dir_inv * (1.0f + kBoxTestMargin)) {
        for (int axis = 0; axis < 3; ++axis) {
            const bool negative = std::signbit(ray.dir[axis]);
            near_plane[axis] = axis + (negative ? 3 : 0);
            far_plane[axis] = axis + (negative ? 0 : 3);
        }
    }
    /// From the slab test's per-ray values (the same 1/d and signs), for a walk that
    /// has them already: the three divisions are not made twice.
    [[gnu::always_inline]] explicit BoxTestRay(const RayPrecomp& pre)
        : origin(pre.origin), dir_inv(pre.dir_inv), near_dir_inv(dir_inv * (1.0f - kBoxTestMargin)),
          far_dir_inv(dir_inv * (1.0f + kBoxTestMargin)) {
        for (int axis = 0; axis < 3; ++axis) {
            const bool negative = pre.dir_negative[axis] != 0;
            near_plane[axis] = axis + (negative ? 3 : 0);
            far_plane[axis] = axis + (negative ? 0 : 3);
        }
    }
    /// The coordinate of the box's plane on `axis` that the ray meets first / last.
    float near_plane_of(const Aabb& box, int axis) const { return (&box.lo.x)[near_plane[axis]]; }
    float far_plane_of(const Aabb& box, int axis) const { return (&box.lo.x)[far_plane[axis]]; }
};

static_assert(sizeof(Aabb) == 6 * sizeof(float), "a box is six floats: lo.x lo.y lo.z hi.x hi.y hi.z");

/// For rays that may hit behind their origin: the raw slab interval `box` moved
/// outwards by the margin, each end by its sign (a product keeps ±inf), then clipped
/// to [t_min, t_max].
[[gnu::always_inline]] inline SlabResult widen_and_clip(SlabResult box, float t_min, float t_max) {
    box.t_enter *= box.t_enter > 0.0f ? 1.0f - kBoxTestMargin : 1.0f + kBoxTestMargin;
    box.t_exit *= box.t_exit > 0.0f ? 1.0f + kBoxTestMargin : 1.0f - kBoxTestMargin;
    box.t_enter = box.t_enter > t_min ? box.t_enter : t_min;
    box.t_exit = box.t_exit < t_max ? box.t_exit : t_max;
    return box;
}

/// The widened slab interval, clipped to [t_min, t_max]. hit() is true for every
/// box the exact slab test hits, and for boxes it misses by less than the margin.
///
/// Per axis only the near and the far plane are used, (plane - o) · 1/d as in
/// slab_interval(), reduced in the same order and with the same NaN rule as
/// slab_test() (a NaN from 0 · inf, an origin on a plane of a ±0 axis, never
/// narrows the interval). The widening costs nothing per box: for t >= 0 the near
/// planes' distances are computed with the slightly smaller 1/d · (1 - margin) and
/// the far planes' with 1/d · (1 + margin), which moves the interval's ends
/// outwards by that relative margin. (Behind the origin, t < 0, that would move
/// them inwards; for rays with t_min < 0, kMayStartBehind, each end is moved by its
/// own sign instead: a per-box test that costs 10% of the speed, so the traversals
/// pick this version once per ray.)
template <bool kMayStartBehind>
[[gnu::always_inline]] inline SlabResult widened_slab_test(const Aabb& box, const BoxTestRay& ray, float t_min,
                                                           float t_max) {
    // Without hits behind the origin, starting from [t_min, t_max] clips the interval
    // as it goes; otherwise the raw ends are needed first, to widen each by its sign.
    const Vec3& near_scale = kMayStartBehind ? ray.dir_inv : ray.near_dir_inv;
    const Vec3& far_scale = kMayStartBehind ? ray.dir_inv : ray.far_dir_inv;
    float enter = kMayStartBehind ? -kInfinity : t_min, exit = kMayStartBehind ? kInfinity : t_max;
    for (int axis = 0; axis < 3; ++axis) {
        const float t_near = (ray.near_plane_of(box, axis) - ray.origin[axis]) * near_scale[axis];
        const float t_far = (ray.far_plane_of(box, axis) - ray.origin[axis]) * far_scale[axis];
        enter = t_near > enter ? t_near : enter;
        exit = t_far < exit ? t_far : exit;
    }
    if constexpr (kMayStartBehind) return widen_and_clip({enter, exit}, t_min, t_max);
    return {enter, exit};
}

}  // namespace accelviz
