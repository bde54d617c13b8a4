#include "core/geometry/triangle.h"

namespace accelviz {

namespace {

/// A corner relative to the ray's origin, sheared so that the ray runs along +z:
/// x, y in the plane the ray pierces at (0, 0), z along the ray (still unscaled).
struct ShearedCorner {
    float x, y, z;
};

ShearedCorner shear(Vec3 p, const Ray& ray, const WatertightRay& r) {
    const Vec3 a = p - ray.origin;
    return {a[r.kx] - r.shear_x * a[r.kz], a[r.ky] - r.shear_y * a[r.kz], a[r.kz]};
}

}  // namespace

PlaneFirstTest plane_first_test(const Triangle& tri, const Ray& ray) {
    PlaneFirstTest r;
    const Vec3 n = cross(tri.edge1, tri.edge2);
    const float n_dot_d = dot(n, ray.dir);
    if (n_dot_d == 0.0f || !std::isfinite(n_dot_d)) {
        r.parallel = true;
        return r;
    }
    r.t = dot(n, tri.p0 - ray.origin) / n_dot_d;
    r.point = ray.origin + ray.dir * r.t;
    const Vec3 p1 = tri.p0 + tri.edge1, p2 = tri.p0 + tri.edge2;
    const Vec3 edge_p1_p2 = tri.edge2 - tri.edge1;
    r.edge[0] = dot(cross(tri.edge1, r.point - tri.p0), n);
    r.edge[1] = dot(cross(edge_p1_p2, r.point - p1), n);
    r.edge[2] = dot(cross(-tri.edge2, r.point - p2), n);
    r.inside = r.edge[0] >= 0.0f && r.edge[1] >= 0.0f && r.edge[2] >= 0.0f;
    r.hit = r.inside && r.t >= ray.t_min && r.t <= ray.t_max;
    return r;
}

TriangleTest intersect_triangle(const TriangleCorners& tri, const Ray& ray, const WatertightRay& sheared,
                                const BoxTestRay& box_ray) {
    TriangleTest r;
    const ShearedCorner a = shear(tri.p0, ray, sheared);
    const ShearedCorner b = shear(tri.p1, ray, sheared);
    const ShearedCorner c = shear(tri.p2, ray, sheared);

    // The edge functions: twice the signed areas of the triangles the origin (the
    // ray) makes with each edge. e0 belongs to the edge b-c (the weight of p0), e1
    // to c-a (p1), e2 to a-b (p2). A neighbour computes its shared edge's function
    // from the same two sheared corners, with the products swapped: the exact
    // negative, as IEEE rounding is symmetric.
    float e0 = c.x * b.y - c.y * b.x;
    float e1 = a.x * c.y - a.y * c.x;
    float e2 = b.x * a.y - b.y * a.x;
    // Rounding is monotone, so a nonzero float edge function has the exact sign; a
    // zero may be rounding. Then all three again in double, where each product of
    // two floats is exact and the difference keeps the exact sign. Their sizes may be
    // rounding too: on a hit (one sign) their sum, det, small beside the products (a
    // sliver seen edge-on) leaves t, their weighted mean of the corners' depths, off
    // the triangle, as Möller–Trumbore's (finish_moller_trumbore). Then too.
    const bool one_sign = (e0 > 0.0f && e1 > 0.0f && e2 > 0.0f) || (e0 < 0.0f && e1 < 0.0f && e2 < 0.0f);
    const bool small_det =
        one_sign && !(std::fabs(e0 + e1 + e2) >=
                      kDetShareForFloat * (std::fabs(c.x * b.y) + std::fabs(c.y * b.x) + std::fabs(a.x * c.y) +
                                           std::fabs(a.y * c.x) + std::fabs(b.x * a.y) + std::fabs(b.y * a.x)));
    if (e0 == 0.0f || e1 == 0.0f || e2 == 0.0f || small_det) {
        e0 = float(double(c.x) * double(b.y) - double(c.y) * double(b.x));
        e1 = float(double(a.x) * double(c.y) - double(a.y) * double(c.x));
        e2 = float(double(b.x) * double(a.y) - double(b.y) * double(a.x));
    }
    // Inside: all three of one sign (zero counts as inside: a closed triangle). NaN
    // corners (a zero-area triangle) fail both.
    const bool inside = (e0 >= 0.0f && e1 >= 0.0f && e2 >= 0.0f) || (e0 <= 0.0f && e1 <= 0.0f && e2 <= 0.0f);
    const float det = e0 + e1 + e2;
    if (det == 0.0f) return r;  // the ray lies in the triangle's plane
    const float inv_det = 1.0f / det;
    r.u = e1 * inv_det;
    r.v = e2 * inv_det;
    // t from the corners' distances along the ray, scaled by 1/d[kz].
    const float t_scaled = e0 * (sheared.shear_z * a.z) + e1 * (sheared.shear_z * b.z) + e2 * (sheared.shear_z * c.z);
    r.t = t_scaled * inv_det;
    if (!inside) return r;
    apply_own_box_rule(tri.box(), ray, box_ray, r);
    return r;
}

}  // namespace accelviz
