#include "core/geometry/triangle_box.h"

#include <algorithm>
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

TriangleAxes::TriangleAxes(Vec3 p0, Vec3 p1, Vec3 p2) {
    const double zero[3] = {0, 0, 0};
    const V3d v[3] = {sub(p0, zero), sub(p1, zero), sub(p2, zero)};
    const V3d edges[3] = {sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])};
    V3d axes[kAxes] = {};
    axes[0] = cross(edges[0], edges[1]);
    for (int a = 0; a < 3; ++a) {
        V3d unit{{0, 0, 0}};
        unit.v[a] = 1;
        for (int e = 0; e < 3; ++e) axes[1 + 3 * a + e] = cross(unit, edges[e]);
    }
    for (int k = 0; k < kAxes; ++k) {
        const double q0 = dot(axes[k], v[0]), q1 = dot(axes[k], v[1]), q2 = dot(axes[k], v[2]);
        lo_[k] = std::min(q0, std::min(q1, q2));
        hi_[k] = std::max(q0, std::max(q1, q2));
        x_[k] = axes[k][0];
        y_[k] = axes[k][1];
        z_[k] = axes[k][2];
    }
    for (int a = 0; a < 3; ++a) {
        box_lo_[a] = std::min(v[0][a], std::min(v[1][a], v[2][a]));
        box_hi_[a] = std::max(v[0][a], std::max(v[1][a], v[2][a]));
    }
}

bool TriangleAxes::overlaps(const Aabb& box) const {
    if (box.empty()) return false;
    double centre[3], half[3];
    for (int a = 0; a < 3; ++a) {
        if (box_lo_[a] > double(box.hi[a]) || box_hi_[a] < double(box.lo[a])) return false;  // 1-3
        centre[a] = 0.5 * (double(box.lo[a]) + box.hi[a]);
        half[a] = 0.5 * (double(box.hi[a]) - box.lo[a]);
    }
    int separated = 0;
    for (int k = 0; k < kAxes; ++k) {  // 4-13, as in triangle_overlaps_box
        const double c = x_[k] * centre[0] + y_[k] * centre[1] + z_[k] * centre[2];
        const double radius = half[0] * std::fabs(x_[k]) + half[1] * std::fabs(y_[k]) + half[2] * std::fabs(z_[k]);
        separated |= int(lo_[k] - c > radius) | int(hi_[k] - c < -radius);
    }
    return separated == 0;
}

ClippedPolygon ClippedPolygon::of_triangle(Vec3 p0, Vec3 p1, Vec3 p2) {
    ClippedPolygon poly;
    poly.count = 3;
    for (int k = 0; k < 3; ++k) {
        poly.v[0][k] = p0[k];
        poly.v[1][k] = p1[k];
        poly.v[2][k] = p2[k];
    }
    return poly;
}

void ClippedPolygon::cut(int axis, double plane, double sign) {
    double d[kMaxCorners];
    for (int i = 0; i < count; ++i) d[i] = sign * (v[i][axis] - plane);
    // Sutherland–Hodgman, each edge taken from its earlier corner to its later one
    // (the last edge from the last corner to the first).
    double out[kMaxCorners][3];
    int n = 0;
    int prev = count - 1;
    for (int i = 0; i < count; prev = i, ++i) {
        if ((d[prev] >= 0) != (d[i] >= 0)) {
            // The edge crosses the plane: add the crossing point, exactly on the plane.
            const double s = d[prev] / (d[prev] - d[i]);
            for (int k = 0; k < 3; ++k) out[n][k] = v[prev][k] + s * (v[i][k] - v[prev][k]);
            out[n][axis] = plane;
            ++n;
        }
        if (d[i] >= 0) {
            for (int k = 0; k < 3; ++k) out[n][k] = v[i][k];
            ++n;
        }
    }
    count = n;
    for (int i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k) v[i][k] = out[i][k];
}

void ClippedPolygon::clip_to(const Aabb& box) {
    if (box.empty()) {
        count = 0;
        return;
    }
    for (int a = 0; a < 3; ++a) {
        keep_side(a, double(box.lo[a]), true);
        keep_side(a, double(box.hi[a]), false);
    }
}

namespace {

/// Bounds [lo, hi] (double) rounded outwards to float, but never beyond `box`.
[[gnu::always_inline]] inline Aabb rounded_within(const double lo[3], const double hi[3], const Aabb& box) {
    Aabb result;
    for (int k = 0; k < 3; ++k) {
        const float down = round_down(lo[k]), up = round_up(hi[k]);
        result.lo[k] = box.lo[k] > down ? box.lo[k] : down;  // as fmax(down, box.lo): down on a tie
        result.hi[k] = box.hi[k] < up ? box.hi[k] : up;
    }
    return result;
}

/// Grows [lo, hi] to hold p. Plain comparisons (no NaN here: corners are finite):
/// std::fmin is a libm call.
void grow(double lo[3], double hi[3], const double p[3]) {
    for (int k = 0; k < 3; ++k) {
        lo[k] = p[k] < lo[k] ? p[k] : lo[k];
        hi[k] = p[k] > hi[k] ? p[k] : hi[k];
    }
}

}  // namespace

Aabb ClippedPolygon::bounds_within(const Aabb& box) const {
    if (count == 0) return {};
    double lo[3] = {v[0][0], v[0][1], v[0][2]}, hi[3] = {lo[0], lo[1], lo[2]};
    for (int i = 1; i < count; ++i) grow(lo, hi, v[i]);
    return rounded_within(lo, hi, box);
}

Aabb ClippedPolygon::side_bounds_within(int axis, double plane, bool keep_above, const Aabb& box) const {
    // keep_side's corners and crossing points, the same arithmetic, taken into the
    // bounds as they come instead of into a new polygon.
    const double sign = keep_above ? 1.0 : -1.0;
    double d[kMaxCorners];
    for (int i = 0; i < count; ++i) d[i] = sign * (v[i][axis] - plane);
    constexpr double inf = std::numeric_limits<double>::infinity();
    double lo[3] = {inf, inf, inf}, hi[3] = {-inf, -inf, -inf};
    bool any = false;
    int prev = count - 1;
    for (int i = 0; i < count; prev = i, ++i) {
        if ((d[prev] >= 0) != (d[i] >= 0)) {
            const double s = d[prev] / (d[prev] - d[i]);
            double p[3];
            for (int k = 0; k < 3; ++k) p[k] = v[prev][k] + s * (v[i][k] - v[prev][k]);
            p[axis] = plane;
            grow(lo, hi, p);
            any = true;
        }
        if (d[i] >= 0) {
            grow(lo, hi, v[i]);
            any = true;
        }
    }
    if (!any) return {};
    return rounded_within(lo, hi, box);
}

Aabb clip_triangle_to_box(Vec3 p0, Vec3 p1, Vec3 p2, const Aabb& box) {
    if (box.empty()) return {};
    ClippedPolygon poly = ClippedPolygon::of_triangle(p0, p1, p2);
    poly.clip_to(box);
    return poly.bounds_within(box);
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
