#pragma once
/// Ray–triangle intersection by barycentric solve (Möller & Trumbore 1997),
/// as in the lecture: o + t d = (1-u-v) p0 + u p1 + v p2, solved by Cramer's rule.

#include <cstdint>

#include "core/math/aabb.h"

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
    /// a "hit" at the ray's origin far from the triangle (found by fuzzing).
    static Triangle from_points(Vec3 p0, Vec3 p1, Vec3 p2) {
        if (has_zero_area(p0, p1, p2)) {
            const Vec3 nan{kNaN, kNaN, kNaN};
            return {p0, nan, nan};
        }
        return {p0, p1 - p0, p2 - p0};
    }
};

/// What one ray–triangle test found. u, v are the barycentric weights of p1, p2.
struct TriangleTest {
    bool hit = false;
    float t = kInfinity;
    float u = 0, v = 0;
};

/// Möller–Trumbore. Hit iff det != 0, u >= 0, v >= 0, u + v <= 1 and
/// t in [t_min, t_max]. Edges and vertices count as inside (closed triangle).
/// No absolute epsilon: det is compared with exactly 0, so tiny and huge meshes
/// behave alike. Every comparison is written so that NaN (the edges of a
/// zero-area triangle, see Triangle::from_points) fails it.
inline TriangleTest intersect_triangle(const Triangle& tri, const Ray& ray) {
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
    r.hit = r.u >= 0.0f && r.v >= 0.0f && r.u + r.v <= 1.0f && r.t >= ray.t_min && r.t <= ray.t_max;
    return r;
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
