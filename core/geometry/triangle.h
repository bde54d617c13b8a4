#pragma once
/// Ray–triangle intersection by barycentric solve (Möller & Trumbore 1997),
/// as in the lecture: o + t d = (1-u-v) p0 + u p1 + v p2, solved by Cramer's rule.

#include <cstdint>

#include <vector>

#include "core/math/box_test.h"
#include "core/util/large_array.h"

namespace accelviz {

/// True for a triangle of zero area: its corners coincide or lie on one line. The
/// cross product of two edges is computed in double, where each product of two
/// floats is exact, so it is zero exactly when the edges (as doubles) are parallel.
inline bool has_zero_area(Vec3 p0, Vec3 p1, Vec3 p2) {
    const double e1[3] = {double(p1.x) - p0.x, double(p1.y) - p0.y, double(p1.z) - p0.z};
    const double e2[3] = {double(p2.x) - p0.x, double(p2.y) - p0.y, double(p2.z) - p0.z};
    return e1[1] * e2[2] == e1[2] * e2[1] && e1[2] * e2[0] == e1[0] * e2[2] && e1[0] * e2[1] == e1[1] * e2[0];
}

/// A triangle as the intersection test wants it: a corner and two edges.
/// Every structure tests triangles through this one form, so every structure
/// computes bit-identical t, u, v for the same ray and triangle.
struct Triangle {
    Vec3 p0;
    Vec3 edge1;  ///< p1 - p0
    Vec3 edge2;  ///< p2 - p0

    /// A zero-area triangle gets NaN edges, so that intersect_triangle never reports
    /// a hit on it. Its det is zero only in exact arithmetic: in float it is rounding
    /// noise, and with numerators that happen to be zero the test accepted u = v = t = 0,
    /// a "hit" at the ray's origin far from the triangle (found by fuzzing). Zero area
    /// as the test sees it counts too: edges that come out parallel once rounded to
    /// float (a sliver 1e-7 wide and 30 long has edge1 == edge2 in float; fuzzing found
    /// such a "hit" far from the sliver, which the octree, rightly, never tested).
    static Triangle from_points(Vec3 p0, Vec3 p1, Vec3 p2) {
        const Vec3 edge1 = p1 - p0, edge2 = p2 - p0;
        if (has_zero_area(p0, p1, p2) || has_zero_area(Vec3{0, 0, 0}, edge1, edge2)) {
            const Vec3 nan{kNaN, kNaN, kNaN};
            return {p0, nan, nan};
        }
        return {p0, edge1, edge2};
    }

    /// The box of the triangle as the test sees it: p0, p0 + edge1, p0 + edge2 in
    /// float (these differ from p1, p2 by rounding when p1 - p0 is not exact).
    Aabb box() const {
        Aabb b;
        for (Vec3 p : {p0, p0 + edge1, p0 + edge2}) b.grow(p);
        return b;
    }
};

/// The structures' arrays of triangles (huge pages: see large_array.h).
using TriangleArray = std::vector<Triangle, LargeArrayAllocator<Triangle>>;

/// The box every structure builds around a triangle: its corners and its corners
/// as the intersection test sees them (Triangle::box), so that it holds the box
/// the test's own-box rule uses (intersect_triangle), bit for bit.
inline Aabb triangle_box(Vec3 p0, Vec3 p1, Vec3 p2) {
    Aabb b = Triangle{p0, p1 - p0, p2 - p0}.box();  // not from_points: a zero-area triangle still has a box
    for (Vec3 p : {p1, p2}) b.grow(p);
    return b;
}

/// What one ray–triangle test found. u, v are the barycentric weights of p1, p2.
struct TriangleTest {
    bool hit = false;
    float t = kInfinity;
    float u = 0, v = 0;
    /// u, v said inside, but the ray misses the triangle's own box: rounding, not
    /// a hit (see intersect_triangle). Only the stepper's inspector asks.
    bool off_own_box = false;
};

/// The own-box rule for a test whose u, v say inside (see intersect_triangle): sets
/// r.hit, or r.off_own_box, and brings r.t into the box. Not inlined: it runs for a
/// small share of the tests, and kept out of the structures' inner loops it leaves
/// them their registers (the cost both ways: docs/performance.md).
[[gnu::noinline]] inline void apply_own_box_rule(const Triangle& tri, const Ray& ray, const BoxTestRay& box_ray,
                                                 TriangleTest& r) {
    // The variant of the widened test the BVH picks for this ray. The interval is not
    // clipped to [t_min, t_max]: t is clamped into the box first (a t just behind the
    // origin stays behind it), then checked.
    const Aabb box = tri.box();
    const SlabResult own = ray.t_min < 0.0f ? widened_slab_test<true>(box, box_ray, -kInfinity, kInfinity)
                                            : widened_slab_test<false>(box, box_ray, -kInfinity, kInfinity);
    if (!(own.t_enter <= own.t_exit) || !(own.t_enter < kInfinity) || !(own.t_exit > -kInfinity)) {
        r.off_own_box = true;
        return;
    }
    r.t = r.t < own.t_enter ? own.t_enter : (r.t > own.t_exit ? own.t_exit : r.t);
    r.hit = r.t >= ray.t_min && r.t <= ray.t_max;
}

/// Möller–Trumbore. Hit iff det != 0, u >= 0, v >= 0, u + v <= 1, the ray meets
/// the triangle's own box, and t (brought into that box) is in [t_min, t_max].
/// Edges and vertices count as inside (closed triangle).
/// No absolute epsilon: det is compared with exactly 0, so tiny and huge meshes
/// behave alike. Every comparison is written so that NaN (the edges of a
/// zero-area triangle, see Triangle::from_points) fails it.
///
/// The own-box rule (as the lecture's KD tree counts a hit only inside the current
/// cell, a hit counts only inside the triangle's own box): in float, u, v and t
/// carry rounding errors that grow as 1/det, so for a sliver triangle the test can
/// report a hit on a ray that misses the triangle's box altogether, or a t outside
/// it. Exact geometry allows neither. So a hit whose ray misses the box, widened
/// exactly as the BVH widens node boxes (box_test.h), is no hit, and t is clamped
/// into the box's interval. This makes every structure agree with brute force by
/// construction: the widened slab interval only grows when the box grows (rounding
/// is monotone), and every node box holds its triangles' boxes (triangle_box), so
/// a node containing a triangle is entered no later than that triangle's t and is
/// never culled before the hit is found. For a well-shaped triangle the clamp seldom
/// moves t (the box is widened by 2^-16 of t, more than the test's usual error), and
/// then towards the exact distance, which lies in the box.
/// `box_ray` is BoxTestRay(ray), computed once per ray by the caller. Always
/// inlined: it is the structures' inner loop, where a call is a measurable cost.
[[gnu::always_inline]] inline TriangleTest intersect_triangle(const Triangle& tri, const Ray& ray, const BoxTestRay& box_ray) {
    TriangleTest r;
    const Vec3 pvec = cross(ray.dir, tri.edge2);
    const float det = dot(tri.edge1, pvec);
    if (det == 0.0f) return r;  // ray parallel to the plane, or zero-area triangle
    const float inv_det = 1.0f / det;
    const Vec3 tvec = ray.origin - tri.p0;
    r.u = dot(tvec, pvec) * inv_det;
    const Vec3 qvec = cross(tvec, tri.edge1);
    r.v = dot(ray.dir, qvec) * inv_det;
    r.t = dot(tri.edge2, qvec) * inv_det;
    if (!(r.u >= 0.0f && r.v >= 0.0f && r.u + r.v <= 1.0f)) return r;
    apply_own_box_rule(tri, ray, box_ray, r);
    return r;
}

/// The same, for a caller that tests one triangle against a ray.
inline TriangleTest intersect_triangle(const Triangle& tri, const Ray& ray) {
    return intersect_triangle(tri, ray, BoxTestRay(ray));
}

/// The closest hit of a ray: triangle id (kNoHit if none), distance t, barycentrics.
struct Hit {
    static constexpr uint32_t kNoHit = 0xffffffffu;
    uint32_t tri = kNoHit;
    float t = kInfinity;
    float u = 0, v = 0;

    bool found() const { return tri != kNoHit; }
};

/// The one order every structure uses to pick the closest hit: smaller t wins,
/// and on an exact tie (a ray through a shared edge) the smaller triangle id.
/// With it, brute force and every acceleration structure agree on the id too.
inline bool is_closer(float t, uint32_t tri, const Hit& best) {
    return t < best.t || (t == best.t && tri < best.tri);
}

}  // namespace accelviz
