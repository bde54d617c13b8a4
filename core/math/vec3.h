#pragma once
/// A 3-component float vector with the handful of operations ray casting needs.
/// Plain data: no invariants. Single precision throughout the core, as in
/// production ray tracers; see math/ray.h for why that is enough.

#include <algorithm>
#include <cmath>

namespace accelviz {

struct Vec3 {
    float x = 0, y = 0, z = 0;

    constexpr Vec3() = default;
    constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}

    constexpr float operator[](int axis) const { return axis == 0 ? x : (axis == 1 ? y : z); }
    constexpr float& operator[](int axis) { return axis == 0 ? x : (axis == 1 ? y : z); }

    constexpr Vec3 operator+(Vec3 b) const { return {x + b.x, y + b.y, z + b.z}; }
    constexpr Vec3 operator-(Vec3 b) const { return {x - b.x, y - b.y, z - b.z}; }
    constexpr Vec3 operator-() const { return {-x, -y, -z}; }
    constexpr Vec3 operator*(float s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3 operator*(Vec3 b) const { return {x * b.x, y * b.y, z * b.z}; }
    constexpr Vec3 operator/(float s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3& operator+=(Vec3 b) { x += b.x; y += b.y; z += b.z; return *this; }
    constexpr Vec3& operator-=(Vec3 b) { x -= b.x; y -= b.y; z -= b.z; return *this; }
    constexpr Vec3& operator*=(float s) { x *= s; y *= s; z *= s; return *this; }
    constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator*(float s, Vec3 v) { return v * s; }
constexpr float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3 cross(Vec3 a, Vec3 b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(Vec3 v) { return std::sqrt(dot(v, v)); }
inline Vec3 normalize(Vec3 v) { return v / length(v); }
constexpr Vec3 min(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
constexpr Vec3 max(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
/// Index (0, 1, 2) of the largest component.
constexpr int max_axis(Vec3 v) { return (v.x >= v.y && v.x >= v.z) ? 0 : (v.y >= v.z ? 1 : 2); }

/// A double-precision twin used where the camera contract asks for exact set-up.
struct Vec3d {
    double x = 0, y = 0, z = 0;
    constexpr Vec3d operator+(Vec3d b) const { return {x + b.x, y + b.y, z + b.z}; }
    constexpr Vec3d operator-(Vec3d b) const { return {x - b.x, y - b.y, z - b.z}; }
    constexpr Vec3d operator*(double s) const { return {x * s, y * s, z * s}; }
    constexpr bool operator==(const Vec3d&) const = default;
};
constexpr double dot(Vec3d a, Vec3d b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr Vec3d cross(Vec3d a, Vec3d b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline Vec3d normalize(Vec3d v) { double l = std::sqrt(dot(v, v)); return {v.x / l, v.y / l, v.z / l}; }
constexpr Vec3 to_float(Vec3d v) { return {float(v.x), float(v.y), float(v.z)}; }
constexpr Vec3d to_double(Vec3 v) { return {v.x, v.y, v.z}; }

}  // namespace accelviz
