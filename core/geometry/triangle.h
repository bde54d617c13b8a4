#pragma once
/// Ray–triangle intersection. Two tests, one chosen per structure (--triangle-test):
/// - Möller–Trumbore (Möller & Trumbore 1997), the lecture's barycentric solve:
///   o + t d = (1-u-v) p0 + u p1 + v p2, solved by Cramer's rule.
/// - The watertight test (Woop, Benthin & Wald 2013, "Watertight Ray/Triangle
///   Intersection", JCGT 2(1)): the triangle is moved into a space where the ray
///   runs along +z from the origin, and three 2D edge functions decide inside.
///   Two triangles sharing an edge compute that edge's function from the same
///   floats, so their signs are exact opposites: a ray cannot slip between them.
///   Möller–Trumbore computes u, v per triangle from different edges, and a ray
///   aimed at a shared edge or vertex can fail every triangle around it.

#include <cmath>
#include <cstdint>
#include <limits>

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/math/box_test.h"
#include "core/util/enum_names.h"
#include "core/util/large_array.h"

namespace accelviz {

/// Which ray–triangle test the structures (and brute force) run.
enum class TriangleTestKind : uint8_t { MollerTrumbore, Watertight };

inline constexpr EnumNames<TriangleTestKind, 2> kTriangleTestNames{{{
    {TriangleTestKind::MollerTrumbore, "mt"},
    {TriangleTestKind::Watertight, "watertight"},
}}};
/// "mt", "watertight".
constexpr std::string_view to_string(TriangleTestKind kind) { return kTriangleTestNames.name(kind); }
constexpr std::optional<TriangleTestKind> parse_triangle_test(std::string_view name) {
    return kTriangleTestNames.parse(name);
}
inline std::vector<std::string> triangle_test_names() { return kTriangleTestNames.names(); }

/// True for a triangle of zero area: its corners coincide or lie on one line. The
/// cross product of two edges is computed in double, where each product of two
/// floats is exact, so it is zero exactly when the edges (as doubles) are parallel.
inline bool has_zero_area(Vec3 p0, Vec3 p1, Vec3 p2) {
    const double e1[3] = {double(p1.x) - p0.x, double(p1.y) - p0.y, double(p1.z) - p0.z};
    const double e2[3] = {double(p2.x) - p0.x, double(p2.y) - p0.y, double(p2.z) - p0.z};
    return e1[1] * e2[2] == e1[2] * e2[1] && e1[2] * e2[0] == e1[0] * e2[2] && e1[0] * e2[1] == e1[1] * e2[0];
}

/// A triangle as Möller–Trumbore wants it: a corner and two edges.
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

/// A triangle as the watertight test wants it: its three corners, as loaded (two
/// triangles sharing a corner must see the same floats). A separate form, kept
/// only by structures built for that test: Möller–Trumbore's stored edges save
/// it two subtractions per test on its critical path (measured: docs/performance.md).
struct TriangleCorners {
    Vec3 p0, p1, p2;

    /// A zero-area triangle gets NaN corners p1, p2, for the same reason as
    /// Triangle::from_points: the edge functions' sum is rounding noise there.
    static TriangleCorners from_points(Vec3 p0, Vec3 p1, Vec3 p2) {
        if (has_zero_area(p0, p1, p2)) {
            const Vec3 nan{kNaN, kNaN, kNaN};
            return {p0, nan, nan};
        }
        return {p0, p1, p2};
    }

    Aabb box() const {
        Aabb b;
        for (Vec3 p : {p0, p1, p2}) b.grow(p);
        return b;
    }
};

/// The structures' arrays of triangles (huge pages: see large_array.h).
using TriangleArray = std::vector<Triangle, LargeArrayAllocator<Triangle>>;
using CornerArray = std::vector<TriangleCorners, LargeArrayAllocator<TriangleCorners>>;

/// The box every structure builds around a triangle: its corners and its corners
/// as Möller–Trumbore sees them (Triangle::box), so that it holds the boxes both
/// tests' own-box rule uses (intersect_triangle), bit for bit.
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

/// What the watertight test needs of a ray, computed once per ray (Woop et al. 2013,
/// section 3): kz is the axis the ray runs along most, kx and ky the other two
/// (swapped when d[kz] < 0, so that the triangles keep their winding), and the
/// shear that maps the direction to (0, 0, 1).
struct WatertightRay {
    int kx = 0, ky = 1, kz = 2;
    float shear_x = 0, shear_y = 0, shear_z = 1;

    WatertightRay() = default;
    explicit WatertightRay(const Ray& ray) {
        const Vec3 a{std::fabs(ray.dir.x), std::fabs(ray.dir.y), std::fabs(ray.dir.z)};
        kz = a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2);
        kx = (kz + 1) % 3;
        ky = (kx + 1) % 3;
        if (ray.dir[kz] < 0.0f) std::swap(kx, ky);
        shear_x = ray.dir[kx] / ray.dir[kz];
        shear_y = ray.dir[ky] / ray.dir[kz];
        shear_z = 1.0f / ray.dir[kz];
    }
};

/// The ray's interval through the box a test sees its triangle in, widened as the BVH
/// widens node boxes (the variant it picks for this ray), or nullopt if the ray misses
/// the box. Not clipped to [t_min, t_max]: the own-box rule clamps t into it first
/// (a t just behind the origin stays behind it), then checks.
inline std::optional<SlabResult> own_box_interval(const Aabb& box, const Ray& ray, const BoxTestRay& box_ray) {
    const SlabResult own = ray.t_min < 0.0f ? widened_slab_test<true>(box, box_ray, -kInfinity, kInfinity)
                                            : widened_slab_test<false>(box, box_ray, -kInfinity, kInfinity);
    if (!(own.t_enter <= own.t_exit) || !(own.t_enter < kInfinity) || !(own.t_exit > -kInfinity)) return std::nullopt;
    return own;
}

/// The own-box rule's second half: t brought into the box's interval, then the hit
/// if it lies in [t_min, t_max].
inline void clamp_into_own_box(const SlabResult& own, const Ray& ray, TriangleTest& r) {
    r.t = r.t < own.t_enter ? own.t_enter : (r.t > own.t_exit ? own.t_exit : r.t);
    r.hit = r.t >= ray.t_min && r.t <= ray.t_max;
}

/// The own-box rule for a test that says inside (see intersect_triangle), with the
/// box the test sees the triangle in: sets r.hit, or r.off_own_box, and brings r.t
/// into the box.
inline void apply_own_box_rule(const Aabb& box, const Ray& ray, const BoxTestRay& box_ray, TriangleTest& r) {
    const std::optional<SlabResult> own = own_box_interval(box, ray, box_ray);
    if (!own) {
        r.off_own_box = true;
        return;
    }
    clamp_into_own_box(*own, ray, r);
}

/// How far below its terms' size Möller–Trumbore's det may fall before float's u,
/// v, t are solved again in double (finish_moller_trumbore): 2^-6. Below it float
/// keeps too few of det's bits. Measured on random slivers seen from 1 to 32 of
/// their lengths away (IllConditionedHits.EveryMollerTrumboreHitLiesOnItsTriangle),
/// every hit then lies within 2^-16 of the ray's size (its distance plus the
/// origin's coordinates) of its triangle: inside the references' padding
/// (reference_padding: 2^-14 of the scene's size) for rays that start within a few
/// scene sizes of it.
inline constexpr float kDetShareForFloat = 0x1p-6f;
/// Below this share even double keeps too few bits (the ray runs in the triangle's
/// plane, or the triangle is a line in all but name): no hit.
inline constexpr double kDetShareForDouble = 0x1p-32;

/// The size of det = edge1 · (dir × edge2)'s terms, none cancelling: what det is
/// compared with to tell whether float kept enough of its bits. In float (Vec3) or
/// double (Vec3d), the same operations in the same order.
template <class V>
auto det_terms_size(const V& e1, const V& d, const V& e2) {
    return std::fabs(e1.x) * (std::fabs(d.y * e2.z) + std::fabs(d.z * e2.y)) +
           std::fabs(e1.y) * (std::fabs(d.z * e2.x) + std::fabs(d.x * e2.z)) +
           std::fabs(e1.z) * (std::fabs(d.x * e2.y) + std::fabs(d.y * e2.x));
}

/// Möller–Trumbore's solve of a candidate hit again in double, from the same floats:
/// each product of two floats is exact there, and the rest keeps about 29 more bits
/// than float. Sets r.u, r.v, r.t; false if it is no hit after all (outside, or det
/// below kDetShareForDouble of its terms). Not inlined: a small share of the small
/// share of tests that reach finish_moller_trumbore.
[[gnu::noinline]] inline bool solve_moller_trumbore_in_double(const Triangle& tri, const Ray& ray,
                                                              TriangleTest& r) {
    const Vec3d d = to_double(ray.dir), e1 = to_double(tri.edge1), e2 = to_double(tri.edge2);
    const Vec3d tvec = to_double(ray.origin) - to_double(tri.p0);
    const Vec3d pvec = cross(d, e2);
    const double det = dot(e1, pvec);
    if (!(std::fabs(det) >= kDetShareForDouble * det_terms_size(e1, d, e2))) {
        r = TriangleTest{};  // as a det of exactly 0: parallel, as far as double can tell
        return false;
    }
    const Vec3d qvec = cross(tvec, e1);
    const double u = dot(tvec, pvec) / det, v = dot(d, qvec) / det;
    r.u = float(u);
    r.v = float(v);
    r.t = float(dot(e2, qvec) / det);
    return u >= 0.0 && v >= 0.0 && u + v <= 1.0;
}

/// Möller–Trumbore's candidate hit (u, v said inside), finished: when det is small
/// beside the products it is the difference of (a sliver triangle, or a ray almost
/// in the plane of a triangle not aligned with the axes), float's u, v, t can be far
/// off, a "hit" on the sliver's box but far from the sliver, where a structure that
/// stores the triangle only in the cells it overlaps rightly never tests it. Such a
/// candidate is solved again in double; the own-box rule, applied as ever, goes
/// first, so that a candidate whose box lies beyond [t_min, t_max] (a triangle
/// behind the closest hit so far: most candidates) skips the question.
/// Not inlined: it runs for a small share of the tests, and kept out of the
/// structures' inner loops it leaves them their registers; defined here, where the
/// compiler sees which registers it uses, so that the loops keep the others across
/// the call (docs/performance.md).
[[gnu::noinline]] inline void finish_moller_trumbore(const Triangle& tri, const Ray& ray, const BoxTestRay& box_ray,
                                                     TriangleTest& r) {
    const std::optional<SlabResult> own = own_box_interval(tri.box(), ray, box_ray);
    if (!own) {
        r.off_own_box = true;
        return;
    }
    if (own->t_enter <= ray.t_max && own->t_exit >= ray.t_min) {
        // det as intersect_triangle computed it, bit for bit, and its terms' size, in
        // float; unless that size is a normal float (products that overflow or
        // underflow), the double solve decides.
        const float det = dot(tri.edge1, cross(ray.dir, tri.edge2));
        const float terms = det_terms_size(tri.edge1, ray.dir, tri.edge2);
        const bool float_holds = std::fabs(det) >= kDetShareForFloat * terms &&
                                 terms >= std::numeric_limits<float>::min() &&
                                 terms <= std::numeric_limits<float>::max();
        if (!float_holds && !solve_moller_trumbore_in_double(tri, ray, r)) return;
    }
    clamp_into_own_box(*own, ray, r);
}

/// Möller–Trumbore. Hit iff det != 0, u >= 0, v >= 0, u + v <= 1 (solved again in
/// double when det is small beside its terms, see finish_moller_trumbore), the ray
/// meets the triangle's own box, and t (brought into that box) is in [t_min, t_max].
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
    finish_moller_trumbore(tri, ray, box_ray, r);
    return r;
}

/// The same, for a caller that tests one triangle against a ray.
inline TriangleTest intersect_triangle(const Triangle& tri, const Ray& ray) {
    return intersect_triangle(tri, ray, BoxTestRay(ray));
}

/// The lecture's first ray-triangle test (回顾：光线与三角形交叉), for the stepper's
/// inspector beside Möller–Trumbore (the structures never run it): the plane first,
/// N = edge1 × edge2, t = N·(p0 - o) / N·d, the point x = o + t·d; then x is inside
/// iff it lies on the inner side of all three edges, ((q - p) × (x - p))·N >= 0 for
/// the edges p -> q = p0 -> p1, p1 -> p2, p2 -> p0. The edges' values are, up to the
/// positive factor |N|², the weights of the opposite corners: edge[0] goes with v (p2's),
/// edge[1] with 1 - u - v (p0's), edge[2] with u (p1's).
struct PlaneFirstTest {
    bool parallel = false;  ///< N·d = 0: the ray runs along the plane (or the triangle has no area)
    float t = kInfinity;
    Vec3 point;             ///< x, where the ray meets the plane
    float edge[3] = {0, 0, 0};
    bool inside = false;    ///< all three edges >= 0
    bool hit = false;       ///< inside and t in [t_min, t_max]
};
PlaneFirstTest plane_first_test(const Triangle& tri, const Ray& ray);

/// Arithmetic per test, counted from the code (plane_first_test and
/// intersect_triangle above; the triangle's p0, edge1, edge2 stored, nothing else;
/// comparisons, and Möller–Trumbore's own-box rule on hits, not counted).
struct OperationCount {
    int multiplies = 0, adds = 0, divides = 0;  ///< adds: additions and subtractions
};
/// N: 6 x 3 ±; N·(p0 - o): 3 x 5 ±; N·d: 3 x 2 ±; t: 1 ÷; x: 3 x 3 ±; the corners
/// p1, p2 and the third edge: 9 ±; per edge x - p, a cross and a dot: 9 x 8 ± (three edges).
inline constexpr OperationCount kPlaneFirstOps{42, 46, 1};
/// pvec: 6 x 3 ±; det: 3 x 2 ±; 1/det: 1 ÷; tvec: 3 ±; u: 4 x 2 ±; qvec: 6 x 3 ±;
/// v: 4 x 2 ±; t: 4 x 2 ±; u + v: 1 ±. (Not counted either: the double solve of an
/// ill-conditioned candidate, finish_moller_trumbore.)
inline constexpr OperationCount kMollerTrumboreOps{27, 18, 1};

/// The watertight test (Woop, Benthin & Wald 2013, figure 10, without backface
/// culling): hit iff the three edge functions have one sign (zero counts as inside:
/// a closed triangle, as Möller–Trumbore's), their sum det != 0, the ray meets the
/// corners' box (the own-box rule, as above) and t, brought into that box, is in
/// [t_min, t_max]. u, v are the weights of p1, p2, as Möller–Trumbore's. Not
/// inlined: it runs only when chosen, and stays out of Möller–Trumbore's loops.
[[gnu::noinline]] TriangleTest intersect_triangle(const TriangleCorners& tri, const Ray& ray,
                                                  const WatertightRay& sheared, const BoxTestRay& box_ray);

/// The same, for a caller that tests one triangle against a ray.
inline TriangleTest intersect_triangle(const TriangleCorners& tri, const Ray& ray) {
    return intersect_triangle(tri, ray, WatertightRay(ray), BoxTestRay(ray));
}

/// One ray's triangle tests against one structure's triangles with test kTest: its
/// per-ray constants, computed once, and the array it reads (`triangles` for
/// Möller–Trumbore, `corners` for the watertight test: the same triangles in the
/// same order; the other may be empty). A structure tests triangle k of its arrays
/// through test(k), so every structure runs the same test the same way (the wide
/// BVH's and the KD tree's Möller–Trumbore leaves run its first half four triangles
/// at a time, bit for bit, and finish each candidate as it does: triangle_lanes.h).
/// The kind is a template parameter, chosen once per ray by the structure, so that
/// Möller–Trumbore's loops hold no call to the other test: such a call, even never
/// taken, cost the BVH 8-10% (its registers saved around it; docs/performance.md).
template <TriangleTestKind kTest>
class TriangleTester {
public:
    [[gnu::always_inline]] TriangleTester(const Ray& ray, const TriangleArray& triangles, const CornerArray& corners)
        : TriangleTester(ray, triangles.data(), corners.data()) {}
    /// For a structure that keeps only one of the arrays (null: the other test's).
    [[gnu::always_inline]] TriangleTester(const Ray& ray, const Triangle* triangles, const TriangleCorners* corners)
        : box_ray_(ray), triangles_(triangles), corners_(corners) {
        if constexpr (kTest == TriangleTestKind::Watertight) watertight_ = WatertightRay(ray);
    }
    /// For a walk that has the ray's slab-test values `pre` (RayPrecomp(ray)) already.
    [[gnu::always_inline]] TriangleTester(const Ray& ray, const RayPrecomp& pre, const TriangleArray& triangles,
                                          const CornerArray& corners)
        : box_ray_(pre), triangles_(triangles.data()), corners_(corners.data()) {
        if constexpr (kTest == TriangleTestKind::Watertight) watertight_ = WatertightRay(ray);
    }

    /// Triangle k of the arrays against `ray` (whose t_max may have shrunk since).
    [[gnu::always_inline]] TriangleTest test(size_t k, const Ray& ray) const {
        if constexpr (kTest == TriangleTestKind::Watertight)
            return intersect_triangle(corners_[k], ray, watertight_, box_ray_);
        else
            return intersect_triangle(triangles_[k], ray, box_ray_);
    }

    const BoxTestRay& box_ray() const { return box_ray_; }

private:
    BoxTestRay box_ray_;
    const Triangle* triangles_;
    const TriangleCorners* corners_;
    WatertightRay watertight_;
};

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
