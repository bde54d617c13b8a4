#pragma once
/// Beyond the first hit, the lecture's last slide: "从表面上一个点看，哪些光源可见
/// （表面是否在阴影中）？表面上可以看到什么反射？" From a point on a surface, is the
/// light visible (a shadow ray: the any-hit query, which may stop at the first
/// occluder), and what does the surface reflect (a reflection ray: the closest-hit
/// query again, from the hit point)? Both run through the same structure, the same
/// traversal code, as the camera's rays.
///
/// Secondary rays start on a surface, where the hit point carries rounding error: a
/// ray started exactly there may hit its own triangle again ("shadow acne"). The
/// start is moved off the surface along the normal by a distance relative to the
/// magnitude of the point's coordinates and of the triangle (the idea of Wächter &
/// Binder 2019, "A Fast and Robust Method for Avoiding Self-Intersection", Ray
/// Tracing Gems ch. 6: the error is a few float ulps of those magnitudes), so the
/// same scene at any scale gets the same picture; there is no absolute epsilon.
/// A secondary ray's hit is found by the same exact query as a camera ray's: the
/// picture is the same through every structure (and brute force).

#include <cstdint>
#include <optional>
#include <vector>

#include "core/geometry/triangle.h"
#include "core/math/aabb.h"
#include "core/math/ray.h"
#include "core/render/image.h"

namespace accelviz {

/// A point light and what the ray caster does with it.
struct Lighting {
    Vec3 light;                 ///< the point light's position
    bool shadows = false;       ///< a shadow ray from every hit to the light (any-hit)
    bool reflections = false;   ///< one bounce off mirror triangles (closest-hit)
    std::vector<uint8_t> mirror;  ///< per triangle id: non-zero = a mirror; empty: none
    bool is_mirror(uint32_t tri) const { return tri < mirror.size() && mirror[tri] != 0; }
};

/// The default light of a scene: above it and to the front right, inside its box
/// (a light outside a closed room such as the Cornell box would light nothing), and
/// off the plane of a flat scene.
Vec3 default_light(const Aabb& scene_bounds);

/// The hit point of `tri` at barycentrics (u, v), computed on the triangle (its
/// error is then the triangle's, whatever the ray's length), moved off the surface
/// to the side `towards` points to (its dot with the normal), by a few ulps of the
/// coordinates' magnitudes.
Vec3 point_off_surface(const Triangle& tri, float u, float v, Vec3 towards);

/// The shadow ray from the hit (`tri` at u, v, seen along `view_dir`) to `light`:
/// direction light - start, so t runs from 0 at the surface to 1 at the light. None
/// when the light is behind the surface as the viewer sees it (the point is unlit;
/// no ray is needed).
std::optional<Ray> shadow_ray(const Triangle& tri, float u, float v, Vec3 view_dir, Vec3 light);

/// The mirror's reflection of a ray arriving along `view_dir` at `tri` (u, v): the
/// direction mirrored in the triangle's plane, from a start off the surface on the
/// viewer's side; [0, inf).
Ray reflection_ray(const Triangle& tri, float u, float v, Vec3 view_dir);

/// The colour of a point lit by the light: the headlight's surface colour (shading.h)
/// at an ambient 0.15 plus 0.85 x cos(normal, direction to the light) when `lit`.
Rgb point_light_shade(const Triangle& tri, Vec3 to_light, bool lit);

/// A mirror's colour: what it reflects, slightly tinted so a mirror reads as one.
Rgb mirror_tint(Rgb reflected);

}  // namespace accelviz
