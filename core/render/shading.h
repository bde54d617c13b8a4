#pragma once
/// Headlight shading shared by the ray caster and the rasterizer, so that where
/// both see the same triangle through the same pixel they give the same colour.

#include <cmath>

#include "core/geometry/triangle.h"
#include "core/render/image.h"

namespace accelviz {

/// Colour of a surface with geometric normal n seen along view direction dir:
/// a light at the eye; brightness |cos| so back faces are lit too.
inline Rgb headlight_shade(const Triangle& tri, Vec3 dir) {
    const Vec3 n = cross(tri.edge1, tri.edge2);
    const float nn = length(n) * length(dir);
    const float c = nn > 0 ? std::fabs(dot(n, dir)) / nn : 0.0f;
    const float k = 0.15f + 0.85f * c;
    return {uint8_t(std::lround(225 * k)), uint8_t(std::lround(205 * k)), uint8_t(std::lround(170 * k))};
}

}  // namespace accelviz
