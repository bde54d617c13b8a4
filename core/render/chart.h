#pragma once
/// Line charts drawn into an Image (no GL), for figures the commands write as PNG:
/// `bench-motion --chart` plots what a moving scene costs with the BVH refitted
/// against rebuilt, time by time; `render --view scaling` (log-log) the frame times
/// of rasterizing and ray casting against the triangle count.

#include <optional>
#include <string>
#include <vector>

#include "core/render/image.h"

namespace accelviz {

struct ChartSeries {
    std::string name;
    Rgb colour;
    std::vector<double> x, y;  ///< the points, in order of x
};

struct LineChart {
    std::string title;
    std::string x_label, y_label;
    std::vector<ChartSeries> series;
    std::optional<double> mark_x;  ///< a vertical line at this x, with `mark_label`
    std::string mark_label;
    /// Both axes logarithmic, whole decades (a power law is a straight line, its
    /// exponent the slope); points with x or y <= 0 are left out.
    bool log_log = false;
    bool legend = true;  ///< the series' names right of the plot (false: the caller lists them)
    int text_scale = 0;  ///< the text's pixel scale (0: from the height, 1 per 240 rows)
};

/// The chart in the rectangle (x0, y0, w, h) of `dst`: axes from the data's range (y
/// from 0, or whole decades when log_log), a few ticks, the series as lines with
/// dots, their names as a legend.
void draw_line_chart(Image& dst, int x0, int y0, int w, int h, const LineChart& chart);

}  // namespace accelviz
