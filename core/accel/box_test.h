#pragma once
/// The BVH's ray–box test: the lecture's slab test (core/math/aabb.h), widened
/// by a few units in the last place so that it never rejects a box around a
/// triangle that Möller–Trumbore accepts.
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
/// interval as usual (NaN-safe, exact for ±0 direction components), then move
/// t_enter down and t_exit up by the relative margin kBoxTestMargin before
/// clipping it to the ray's [t_min, t_max]. Ize's margin 2γ₃ covers the slab
/// test's own rounding; ours is a few times larger to cover Möller–Trumbore's too.
/// The cost of a wider box is only an occasional extra node visit: the answer
/// is decided by the triangle tests, exactly as in brute force.

#include "core/math/aabb.h"

namespace accelviz {

/// Relative slack of the BVH box test: 2^-20 (about 1e-6, 16 ulps).
inline constexpr float kBoxTestMargin = 0x1.0p-16f;

/// The widened slab interval, clipped to [t_min, t_max]. hit() is true for every
/// box the exact slab test hits, and for boxes it misses by less than the margin.
inline SlabResult widened_slab_test(const Aabb& box, const RayPrecomp& ray, float t_min, float t_max) {
    const SlabResult raw = slab_test(box, ray);  // unclipped: [-inf, +inf] to start
    // Scale towards -inf / +inf; a product keeps ±inf as they are (no inf - inf).
    const float enter = raw.t_enter * (raw.t_enter > 0.0f ? 1.0f - kBoxTestMargin : 1.0f + kBoxTestMargin);
    const float exit = raw.t_exit * (raw.t_exit > 0.0f ? 1.0f + kBoxTestMargin : 1.0f - kBoxTestMargin);
    return {enter > t_min ? enter : t_min, exit < t_max ? exit : t_max};
}

}  // namespace accelviz
