#pragma once
/// A ray r(t) = origin + t * dir, valid for t in [t_min, t_max].
/// `dir` need not be normalised; camera rays are, so their t is a distance.

#include <limits>

#include "core/math/vec3.h"

namespace accelviz {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

struct Ray {
    Vec3 origin;
    Vec3 dir;
    float t_min = 0.0f;
    float t_max = kInfinity;
    bool operator==(const Ray&) const = default;  ///< the same ray, bit for bit
};

/// Per-ray values every box test reuses: 1/dir (±inf for ±0 components, as the
/// lecture's slab test wants) and the sign of each component (the near slab).
struct RayPrecomp {
    Vec3 origin;
    Vec3 dir;
    Vec3 dir_inv;
    int dir_negative[3];

    [[gnu::always_inline]] explicit RayPrecomp(const Ray& ray)
        : origin(ray.origin), dir(ray.dir),
          dir_inv(1.0f / ray.dir.x, 1.0f / ray.dir.y, 1.0f / ray.dir.z),
          // signbit, not `< 0`: a -0 component divides to -inf, so its near slab is the max side.
          dir_negative{std::signbit(ray.dir.x) ? 1 : 0, std::signbit(ray.dir.y) ? 1 : 0,
                       std::signbit(ray.dir.z) ? 1 : 0} {}
};

}  // namespace accelviz
