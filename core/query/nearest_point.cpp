#include "core/query/nearest_point.h"

namespace accelviz {

Vec3d closest_point_on_triangle(Vec3d p, Vec3d a, Vec3d b, Vec3d c) {
    // Inside the prism over the triangle (p on the inner side of the plane through each
    // edge and the normal n), the nearest point is p's projection onto the plane.
    // The three sides are told apart by the signs of (edge × (p - corner)) · n, whose
    // terms keep their bits on a sliver: Ericson's (2005, 5.1.5) Voronoi-region tests
    // take differences of products of dot products, which on a triangle 2^-25 as wide
    // as long cancel to rounding noise and pick a far vertex or edge.
    const Vec3d ab = b - a, bc = c - b, ca = a - c;
    const Vec3d n = cross(ab, c - a);
    const double n2 = dot(n, n);
    if (n2 > 0 && dot(cross(ab, p - a), n) >= 0 && dot(cross(bc, p - b), n) >= 0 && dot(cross(ca, p - c), n) >= 0)
        return p - n * (dot(p - a, n) / n2);
    // Outside it (or a triangle without area: a segment or a point), the nearest point
    // lies on the boundary: the nearest of the three edges' nearest points.
    auto on_segment = [&](Vec3d s, Vec3d d) {
        const double len2 = dot(d, d);
        const double t = len2 > 0 ? std::clamp(dot(p - s, d) / len2, 0.0, 1.0) : 0.0;
        return s + d * t;
    };
    Vec3d best = on_segment(a, ab);
    for (const Vec3d& q : {on_segment(b, bc), on_segment(c, ca)})
        if (dot(q - p, q - p) < dot(best - p, best - p)) best = q;
    return best;
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
