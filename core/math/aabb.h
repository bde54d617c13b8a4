#pragma once
/// Axis-aligned bounding box and the lecture's slab test.

#include <array>

#include "core/math/ray.h"

namespace accelviz {

/// An axis-aligned box [lo, hi]. The default box is empty (lo = +inf, hi = -inf),
/// so growing it by any point gives that point.
struct Aabb {
    Vec3 lo{kInfinity, kInfinity, kInfinity};
    Vec3 hi{-kInfinity, -kInfinity, -kInfinity};

    bool empty() const { return !(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z); }
    void grow(Vec3 p) { lo = min(lo, p); hi = max(hi, p); }
    void grow(const Aabb& b) { lo = min(lo, b.lo); hi = max(hi, b.hi); }
    Vec3 extent() const { return hi - lo; }
    Vec3 center() const { return (lo + hi) * 0.5f; }
    /// Surface area (0 for an empty box): the SAH's hit probability is a ratio of these.
    float area() const {
        if (empty()) return 0.0f;
        Vec3 e = extent();
        return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
    }
    bool contains(const Aabb& b) const {
        return lo.x <= b.lo.x && lo.y <= b.lo.y && lo.z <= b.lo.z &&
               hi.x >= b.hi.x && hi.y >= b.hi.y && hi.z >= b.hi.z;
    }
    bool contains(Vec3 p) const {
        return lo.x <= p.x && lo.y <= p.y && lo.z <= p.z && hi.x >= p.x && hi.y >= p.y && hi.z >= p.z;
    }
    bool operator==(const Aabb&) const = default;
};

inline Aabb merge(Aabb a, const Aabb& b) { a.grow(b); return a; }

/// A splitting plane drawn as a rectangle: where the plane x_axis = position cuts
/// `box`, corners in order around the edge (KD/octree planes, a BVH split).
inline std::array<Vec3, 4> plane_across_box(const Aabb& box, int axis, float position) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    const float us[4] = {box.lo[u], box.hi[u], box.hi[u], box.lo[u]};
    const float vs[4] = {box.lo[v], box.lo[v], box.hi[v], box.hi[v]};
    std::array<Vec3, 4> corners;
    for (int k = 0; k < 4; ++k) {
        corners[k][axis] = position;
        corners[k][u] = us[k];
        corners[k][v] = vs[k];
    }
    return corners;
}

/// The slab interval of one axis: where the ray is between the two planes.
struct SlabInterval {
    float t_min;
    float t_max;
};

/// Result of the slab test, unclipped: t_enter = max of the per-axis t_min,
/// t_exit = min of the per-axis t_max (lecture: 光线与轴对齐包围盒相交).
struct SlabResult {
    float t_enter;
    float t_exit;
    /// The box is hit iff the ray spends time inside it at some t >= 0.
    bool hit() const { return t_enter <= t_exit && t_exit >= 0.0f; }
};

/// One axis of the slab test. For a zero direction component 1/d is ±inf:
/// the interval is (-inf, +inf) if the origin lies between the planes and empty
/// otherwise. When the origin lies exactly on a plane, (plane - o) * inf is
/// 0 * inf = NaN; slab_test() below ignores NaN bounds, which is exactly right
/// (an origin on the plane is inside the closed slab).
[[gnu::always_inline]] inline SlabInterval slab_interval(const Aabb& box, const RayPrecomp& ray, int axis) {
    const float t_lo = (box.lo[axis] - ray.origin[axis]) * ray.dir_inv[axis];
    const float t_hi = (box.hi[axis] - ray.origin[axis]) * ray.dir_inv[axis];
    return ray.dir_negative[axis] ? SlabInterval{t_hi, t_lo} : SlabInterval{t_lo, t_hi};
}

/// The slab test, starting from the interval [t_enter, t_exit] given (use
/// [-inf, +inf] for the lecture's raw numbers, or the ray's valid range to clip).
/// NaN-safe: `a > b ? a : b` keeps b when a is NaN, so a NaN bound never narrows
/// the interval.
[[gnu::always_inline]] inline SlabResult slab_test(const Aabb& box, const RayPrecomp& ray, float t_enter = -kInfinity,
                                                   float t_exit = kInfinity) {
    for (int axis = 0; axis < 3; ++axis) {
        const SlabInterval s = slab_interval(box, ray, axis);
        t_enter = s.t_min > t_enter ? s.t_min : t_enter;
        t_exit = s.t_max < t_exit ? s.t_max : t_exit;
    }
    return {t_enter, t_exit};
}

}  // namespace accelviz
