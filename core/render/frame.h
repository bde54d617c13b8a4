#pragma once
/// What a renderer (ray caster or rasterizer) produces for one camera: colour,
/// the hit distance t per pixel (+inf for background), the triangle seen, and
/// the work done per pixel.

#include <cstdint>
#include <vector>

#include "core/geometry/triangle.h"
#include "core/render/image.h"
#include "core/traversal/observers.h"

namespace accelviz {

/// The work of one kind of secondary ray (shadow or reflection; lighting.h), counted
/// like the primary rays' (RayCastOptions::count_work).
struct SecondaryWork {
    std::vector<uint32_t> nodes;  ///< per pixel: nodes/cells visited by its rays of this kind
    std::vector<uint32_t> tests;  ///< per pixel: their triangle tests
    Counters work;                ///< summed over all pixels
    uint64_t rays = 0;            ///< how many were traced
};

struct Frame {
    int width = 0, height = 0;
    Image colour;
    std::vector<float> depth;      ///< hit distance t along the pixel's ray; +inf if none
    std::vector<uint32_t> tri;     ///< triangle id, Hit::kNoHit if none
    std::vector<uint32_t> nodes;   ///< per pixel: nodes/cells visited (ray caster with counters)
    std::vector<uint32_t> tests;   ///< per pixel: triangle tests (ray caster) or fragments (raster)
    Counters work;                 ///< ray caster with counters: the work summed over all pixels
    SecondaryWork shadow;          ///< with a light, shadows and counters: the shadow rays' work
    SecondaryWork reflection;      ///< with reflections and counters: the reflection rays' work

    Frame() = default;
    Frame(int w, int h)
        : width(w), height(h), colour(w, h), depth(size_t(w) * h, kInfinity),
          tri(size_t(w) * h, Hit::kNoHit) {}
    size_t index(int x, int y) const { return size_t(y) * width + x; }
};

/// The background colour of every view.
inline constexpr Rgb kBackground{32, 36, 44};

}  // namespace accelviz
