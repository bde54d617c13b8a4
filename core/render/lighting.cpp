#include "core/render/lighting.h"

#include <algorithm>
#include <cmath>

#include "core/render/shading.h"

namespace accelviz {
namespace {

float max_abs(Vec3 v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); }

/// The unit normal of `tri` on the side `towards` points to.
Vec3 normal_towards(const Triangle& tri, Vec3 towards) {
    const Vec3 n = normalize(cross(tri.edge1, tri.edge2));
    return dot(n, towards) < 0 ? n * -1.0f : n;
}

/// How far a start is moved off the surface: 2^-19 of the largest coordinate
/// magnitude the hit point was computed from, 16 to 32 float ulps of it, so the
/// distance scales with the scene. (Wächter & Binder move by 256 ulps of each
/// coordinate; on a tilted floor of small triangles, acne showed at 1 ulp and was
/// gone from 4, at every scale from 1e-6 to 1e6: 16 leaves a margin.)
constexpr float kOffsetFraction = 1.0f / 524288.0f;

}  // namespace

Vec3 default_light(const Aabb& scene_bounds) {
    const Vec3 centre = (scene_bounds.lo + scene_bounds.hi) * 0.5f, extent = scene_bounds.hi - scene_bounds.lo;
    // Each side at least a quarter of the longest: a flat scene (a floor, one triangle)
    // gets its light off its plane, where it lights one side.
    const float floor = 0.25f * std::max({extent.x, extent.y, extent.z});
    const Vec3 e = max(extent, Vec3{floor, floor, floor});
    return centre + Vec3{0.3f * e.x, 0.45f * e.y, 0.3f * e.z};
}

Vec3 point_off_surface(const Triangle& tri, float u, float v, Vec3 towards) {
    const Vec3 p = tri.p0 + tri.edge1 * u + tri.edge2 * v;
    const float magnitude = std::max({max_abs(p), max_abs(tri.p0), max_abs(tri.edge1), max_abs(tri.edge2)});
    return p + normal_towards(tri, towards) * (magnitude * kOffsetFraction);
}

std::optional<Ray> shadow_ray(const Triangle& tri, float u, float v, Vec3 view_dir, Vec3 light) {
    const Vec3 viewer_side = view_dir * -1.0f;
    const Vec3 start = point_off_surface(tri, u, v, viewer_side);
    const Vec3 to_light = light - start;
    const Vec3 n = cross(tri.edge1, tri.edge2);
    // The light must be on the side the surface is seen from (it lights that side only).
    if (!(dot(n, to_light) * dot(n, viewer_side) > 0)) return std::nullopt;
    return Ray{start, to_light, 0.0f, 1.0f};
}

Ray reflection_ray(const Triangle& tri, float u, float v, Vec3 view_dir) {
    const Vec3 d = normalize(view_dir);
    const Vec3 n = normalize(cross(tri.edge1, tri.edge2));
    const Vec3 r = d - n * (2.0f * dot(d, n));
    return Ray{point_off_surface(tri, u, v, d * -1.0f), r, 0.0f, kInfinity};
}

Rgb point_light_shade(const Triangle& tri, Vec3 to_light, bool lit) {
    float k = 0.15f;
    if (lit) {
        const Vec3 n = cross(tri.edge1, tri.edge2);
        const float nn = length(n) * length(to_light);
        k += 0.85f * (nn > 0 ? std::fabs(dot(n, to_light)) / nn : 0.0f);
    }
    return {uint8_t(std::lround(225 * k)), uint8_t(std::lround(205 * k)), uint8_t(std::lround(170 * k))};
}

Rgb mirror_tint(Rgb reflected) {
    // A silver-blue glass: 80 % of red, 88 % of green, all of blue.
    return {uint8_t(std::lround(reflected.r * 0.80f)), uint8_t(std::lround(reflected.g * 0.88f)), reflected.b};
}

}  // namespace accelviz
