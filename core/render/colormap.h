#pragma once
/// A perceptual colour map (dark blue → green → yellow, like matplotlib's
/// viridis: brightness rises monotonically, readable in grey and by most
/// colour-blind viewers) for heat maps of per-pixel work.

#include <algorithm>
#include <cmath>

#include "core/render/image.h"

namespace accelviz {

/// Colour for x in [0, 1] (clamped).
inline Rgb colormap(double x) {
    // Five anchors sampled from viridis, linearly interpolated.
    static constexpr Rgb kAnchors[] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
    constexpr int n = 5;
    if (!(x > 0)) return kAnchors[0];
    if (x >= 1) return kAnchors[n - 1];
    const double f = x * (n - 1);
    const int i = std::min(int(f), n - 2);
    const double w = f - i;
    auto mix = [&](uint8_t a, uint8_t b) { return uint8_t(std::lround(a + (b - a) * w)); };
    return {mix(kAnchors[i].r, kAnchors[i + 1].r), mix(kAnchors[i].g, kAnchors[i + 1].g),
            mix(kAnchors[i].b, kAnchors[i + 1].b)};
}

}  // namespace accelviz
