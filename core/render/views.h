#pragma once
/// The CPU-composed views of `accelviz render`: raster and ray cast side by side,
/// where their depths disagree, and heat maps of per-pixel work. Plain images;
/// the window shows the same pictures as textures.

#include <array>
#include <optional>
#include <string>

#include "core/render/frame.h"
#include "core/render/rasterizer.h"
#include "core/traversal/observers.h"

namespace accelviz {

/// How two depth images agree (foundation issue's raster-vs-ray-cast measure).
struct DepthAgreement {
    size_t pixels = 0;             ///< all pixels
    size_t covered_by_both = 0;    ///< both saw a surface
    size_t agreeing = 0;           ///< of those, |t_a - t_b| <= rel_tol * max(t_a, t_b)
    size_t coverage_differs = 0;   ///< exactly one of them saw a surface
    double max_relative_error = 0; ///< over pixels covered by both
    double agreeing_percent() const { return covered_by_both ? 100.0 * agreeing / covered_by_both : 100.0; }
    double coverage_differs_percent() const { return pixels ? 100.0 * coverage_differs / pixels : 0.0; }
};

/// Compares two frames' depths pixel by pixel.
DepthAgreement compare_depths(const Frame& a, const Frame& b, double rel_tol = 1e-4);

/// What each renderer did, for the labels.
struct WorkSummary {
    std::string accel_name;   ///< structure used by the ray caster
    Counters ray_work;        ///< summed over all pixels (when counted)
    bool ray_work_counted = false;
    RasterStats raster_work;
};

/// Raster (left) and ray cast (right), each width x height, side by side with labels.
Image split_view(const Frame& raster, const Frame& ray, const WorkSummary& work);

/// Where raster and ray cast disagree: grey = agree (shaded by depth), colour
/// scale = relative depth error, magenta = only the rasterizer drew, cyan = only
/// the ray caster hit. With a legend and the agreement figures.
Image depth_diff_view(const Frame& raster, const Frame& ray, double rel_tol = 1e-4);
/// depth_diff_view's colours alone, for a caller that draws the text in its own font.
Image depth_diff_colours(const Frame& raster, const Frame& ray, double rel_tol = 1e-4);
/// The tick labels of depth_diff_view's colour bar: rel_tol, the middle, 1000 * rel_tol.
std::array<std::string, 3> depth_diff_ticks(double rel_tol = 1e-4);

/// Depth as grey (near = light, far = dark), over [t_near, t_far].
Image depth_grey_view(const Frame& frame, float t_near, float t_far);

/// The numbers a heat map's legend shows.
struct HeatScale {
    double max_value = 1;              ///< the count drawn in the colour map's top colour
    double mean = 0;                   ///< the mean count per pixel
    std::array<std::string, 3> ticks;  ///< labels at 0, the middle and the top
};
/// The scale of a heat map on [0, max_value] (max_value <= 0: the counts' own maximum).
HeatScale heat_scale(const std::vector<uint32_t>& counts, double max_value);
/// A heat map's colours alone, for a caller that draws the legend in its own font.
Image heat_colours(const std::vector<uint32_t>& counts, int width, int height, const HeatScale& scale);

/// Heat map of per-pixel counts (Frame::nodes or Frame::tests) on [0, max_value]
/// (max_value <= 0: the frame's own maximum), with a legend showing the numbers.
Image heat_view(const std::vector<uint32_t>& counts, int width, int height, const std::string& title,
                double max_value);

}  // namespace accelviz
