#include "core/geometry/triangle_box.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace accelviz {

namespace {

struct V3d {
    double v[3];
    double operator[](int a) const { return v[a]; }
};
V3d sub(Vec3 a, const double c[3]) { return {{double(a.x) - c[0], double(a.y) - c[1], double(a.z) - c[2]}}; }
V3d sub(const V3d& a, const V3d& b) { return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}}; }
V3d cross(const V3d& a, const V3d& b) {
    return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}
double dot(const V3d& a, const V3d& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// True if `axis` separates the triangle (vertices v, box centred at 0) from the box.
bool separates(const V3d& axis, const V3d v[3], const double half[3]) {
    const double p0 = dot(axis, v[0]), p1 = dot(axis, v[1]), p2 = dot(axis, v[2]);
    const double radius = half[0] * std::fabs(axis[0]) + half[1] * std::fabs(axis[1]) + half[2] * std::fabs(axis[2]);
    const double lo = std::fmin(p0, std::fmin(p1, p2));
    const double hi = std::fmax(p0, std::fmax(p1, p2));
    return lo > radius || hi < -radius;  // touching (== radius) is overlap
}

/// The float just below f (f not NaN, not -inf): std::nextafter(f, -inf) without
/// libm's call, which the clipping below made six times per reference it cut.
float next_float_down(float f) {
    if (f == 0.0f) return -std::numeric_limits<float>::denorm_min();
    const auto bits = std::bit_cast<uint32_t>(f);
    return std::bit_cast<float>(f > 0.0f ? bits - 1 : bits + 1);
}

/// Largest float <= x and smallest float >= x: rounding a double outwards.
float round_down(double x) {
    const float f = float(x);
    return double(f) > x ? next_float_down(f) : f;
}
float round_up(double x) {
    const float f = float(x);
    return double(f) < x ? -next_float_down(-f) : f;
}

}  // namespace

bool triangle_overlaps_box(Vec3 p0, Vec3 p1, Vec3 p2, const Aabb& box) {
    if (box.empty()) return false;
    // Work relative to the box centre, so the box is [-half, half].
    const double centre[3] = {0.5 * (double(box.lo.x) + box.hi.x), 0.5 * (double(box.lo.y) + box.hi.y),
                              0.5 * (double(box.lo.z) + box.hi.z)};
    const double half[3] = {0.5 * (double(box.hi.x) - box.lo.x), 0.5 * (double(box.hi.y) - box.lo.y),
                            0.5 * (double(box.hi.z) - box.lo.z)};
    const V3d v[3] = {sub(p0, centre), sub(p1, centre), sub(p2, centre)};

    // 1-3: the box's face normals (the triangle's box against the box).
    for (int a = 0; a < 3; ++a) {
        V3d axis{{0, 0, 0}};
        axis.v[a] = 1;
        if (separates(axis, v, half)) return false;
    }
    // 4: the triangle's normal (its plane against the box). Zero for a degenerate triangle.
    const V3d edges[3] = {sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
    if (separates(cross(edges[0], edges[1]), v, half)) return false;
    // 5-13: box axis × triangle edge.
    for (int a = 0; a < 3; ++a) {
        V3d unit{{0, 0, 0}};
        unit.v[a] = 1;
        for (const V3d& e : edges)
            if (separates(cross(unit, e), v, half)) return false;
    }
    return true;
}

Aabb clip_triangle_to_box(Vec3 p0, Vec3 p1, Vec3 p2, const Aabb& box) {
    if (box.empty()) return {};
    // A convex polygon clipped by 6 half-spaces has at most 3 + 6 vertices.
    constexpr int kMax = 9;
    V3d buffers[2][kMax + 1];
    V3d* poly = buffers[0];
    V3d* next = buffers[1];
    int count = 3;
    const double zero[3] = {0, 0, 0};
    poly[0] = sub(p0, zero);
    poly[1] = sub(p1, zero);
    poly[2] = sub(p2, zero);
    for (int a = 0; a < 3 && count > 0; ++a) {
        for (int side = 0; side < 2 && count > 0; ++side) {
            // Keep the part with sign * (x_a - plane) >= 0: x >= lo, or x <= hi.
            const double plane = side == 0 ? double(box.lo[a]) : double(box.hi[a]);
            const double sign = side == 0 ? 1.0 : -1.0;
            // A plane with every corner on the kept side changes nothing (most planes of
            // a cell that a triangle straddles on one axis only): skip its pass.
            int inside = 0;
            for (int i = 0; i < count; ++i) inside += sign * (poly[i][a] - plane) >= 0 ? 1 : 0;
            if (inside == count) continue;
            if (inside == 0) return {};
            int out = 0;
            for (int i = 0; i < count; ++i) {
                const V3d& cur = poly[i];
                const V3d& nxt = poly[(i + 1) % count];
                const double dc = sign * (cur[a] - plane), dn = sign * (nxt[a] - plane);
                if (dc >= 0) next[out++] = cur;
                if ((dc >= 0) != (dn >= 0)) {
                    // The edge crosses the plane: add the crossing point, exactly on the plane.
                    const double s = dc / (dc - dn);
                    V3d p;
                    for (int k = 0; k < 3; ++k) p.v[k] = cur[k] + s * (nxt[k] - cur[k]);
                    p.v[a] = plane;
                    next[out++] = p;
                }
            }
            count = out;
            std::swap(poly, next);
        }
    }
    if (count == 0) return {};
    double lo[3] = {poly[0][0], poly[0][1], poly[0][2]}, hi[3] = {lo[0], lo[1], lo[2]};
    for (int i = 1; i < count; ++i)
        for (int k = 0; k < 3; ++k) {
            // Plain comparisons (no NaN here: vertices are finite): std::fmin is a libm call.
            lo[k] = poly[i][k] < lo[k] ? poly[i][k] : lo[k];
            hi[k] = poly[i][k] > hi[k] ? poly[i][k] : hi[k];
        }
    Aabb result;
    for (int k = 0; k < 3; ++k) {
        // Outwards to float, but never beyond the clipping box.
        const float down = round_down(lo[k]), up = round_up(hi[k]);
        result.lo[k] = box.lo[k] > down ? box.lo[k] : down;  // as fmax(down, box.lo): down on a tie
        result.hi[k] = box.hi[k] < up ? box.hi[k] : up;
    }
    return result;
}

float reference_padding(const Aabb& scene_bounds) {
    if (scene_bounds.empty()) return 0.0f;
    float magnitude = 0.0f;
    for (int a = 0; a < 3; ++a)
        magnitude = std::fmax(magnitude, std::fmax(std::fmax(std::fabs(scene_bounds.lo[a]), std::fabs(scene_bounds.hi[a])),
                                                   scene_bounds.hi[a] - scene_bounds.lo[a]));
    // 2^-14 of the magnitude; never zero, so comparisons against a padded box stay closed.
    return std::fmax(std::ldexp(magnitude, -14), 1e-30f);
}

}  // namespace accelviz
