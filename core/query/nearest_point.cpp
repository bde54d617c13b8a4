#include "core/query/nearest_point.h"

namespace accelviz {

Vec3d closest_point_on_triangle(Vec3d p, Vec3d a, Vec3d b, Vec3d c) {
    // Ericson (2005), 5.1.5: which Voronoi region of the triangle p falls in.
    const Vec3d ab = b - a, ac = c - a, ap = p - a;
    const double d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;  // vertex region a
    const Vec3d bp = p - b;
    const double d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;  // vertex region b
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) return a + ab * (d1 / (d1 - d3));  // edge ab
    const Vec3d cp = p - c;
    const double d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;  // vertex region c
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) return a + ac * (d2 / (d2 - d6));  // edge ac
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0 && (d4 - d3) + (d5 - d6) > 0)
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));  // edge bc
    const double sum = va + vb + vc;
    if (!(sum > 0)) {
        // A degenerate triangle (its corners on one line, or a zero-length edge the
        // divisions above would fail on):
        // the nearest of its three edges' nearest points.
        auto on_segment = [&](Vec3d s, Vec3d e) {
            const Vec3d d = e - s;
            const double len2 = dot(d, d);
            const double t = len2 > 0 ? std::clamp(dot(p - s, d) / len2, 0.0, 1.0) : 0.0;
            return s + d * t;
        };
        Vec3d best = on_segment(a, b);
        for (const Vec3d& q : {on_segment(b, c), on_segment(c, a)})
            if (dot(q - p, q - p) < dot(best - p, best - p)) best = q;
        return best;
    }
    const double v = vb / sum, w = vc / sum;  // inside the face
    return a + ab * v + ac * w;
}

double box_distance_squared(Vec3d p, const Aabb& box) {
    if (box.empty()) return std::numeric_limits<double>::infinity();
    double d2 = 0;
    const double pc[3] = {p.x, p.y, p.z};
    for (int a = 0; a < 3; ++a) {
        const double lo = box.lo[a], hi = box.hi[a];
        const double d = pc[a] < lo ? lo - pc[a] : pc[a] > hi ? pc[a] - hi : 0.0;
        d2 += d * d;
    }
    return d2;
}

}  // namespace accelviz
