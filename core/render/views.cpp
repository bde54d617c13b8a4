#include "core/render/views.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/render/colormap.h"

namespace accelviz {
namespace {

/// Text size for labels: readable on a projector at any image size.
int label_scale(int image_height) { return std::max(1, image_height / 240); }

std::string fmt(const char* format, double value) {
    char buf[64];
    std::snprintf(buf, sizeof buf, format, value);
    return buf;
}

/// Thousands separators: 1234567 -> "1,234,567".
std::string with_commas(uint64_t n) {
    const std::string digits = std::to_string(n);
    std::string out;
    for (size_t i = 0; i < digits.size(); ++i) {
        if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
        out += digits[i];
    }
    return out;
}

/// A horizontal colour bar over [0, 1] of the colour map, on a black box, with a
/// title above and three tick labels (left, middle, right) below. On a small image,
/// where the title is wider than the bar, the bar widens to the title (so the ticks
/// have room too) and the legend moves left as far as it must to stay in the image.
void draw_legend_bar(Image& img, int x, int y, int w, int h, const std::string& title,
                     const std::array<std::string, 3>& ticks) {
    const int s = label_scale(img.height);
    int title_w = 0, title_h = 0;
    text_size(title, s, &title_w, &title_h);
    int tick_w[3] = {0, 0, 0}, th = 0;
    for (int k = 0; k < 3; ++k) text_size(ticks[k], s, &tick_w[k], &th);
    // Wide enough for the title and the two end ticks; the middle tick (centred) only
    // where it fits between them with a gap, so no two labels ever overlap.
    const int gap = 3 * s;
    w = std::max({w, title_w, tick_w[0] + tick_w[2] + gap});
    const bool middle = 2 * std::max(tick_w[0], tick_w[2]) + tick_w[1] + 2 * gap <= w;
    x = std::max(4 * s, std::min(x, img.width - w - 4 * s));
    fill_rect(img, x - 4 * s, y - th - 6 * s, w + 8 * s, h + 2 * th + 10 * s, {0, 0, 0});
    draw_text(img, x, y - th - 3 * s, title, s, {255, 255, 255});
    for (int i = 0; i < w; ++i) fill_rect(img, x + i, y, 1, h, colormap(double(i) / std::max(1, w - 1)));
    for (int k = 0; k < 3; ++k) {
        if (k == 1 && !middle) continue;
        const int lx = std::clamp(x + k * (w - 1) / 2 - tick_w[k] / 2, x, x + w - tick_w[k]);
        draw_text(img, lx, y + h + 2 * s, ticks[k], s, {255, 255, 255});
    }
}

/// Tick label of a count scale: whole numbers with separators, or 2 digits below 10.
std::string count_label(double v) { return v >= 10 ? with_commas(uint64_t(std::lround(v))) : fmt("%.2g", v); }

}  // namespace

DepthAgreement compare_depths(const Frame& a, const Frame& b, double rel_tol) {
    DepthAgreement r;
    r.pixels = a.depth.size();
    for (size_t i = 0; i < a.depth.size() && i < b.depth.size(); ++i) {
        const bool ha = std::isfinite(a.depth[i]), hb = std::isfinite(b.depth[i]);
        if (ha != hb) { ++r.coverage_differs; continue; }
        if (!ha) continue;
        ++r.covered_by_both;
        const double ta = a.depth[i], tb = b.depth[i];
        const double rel = std::fabs(ta - tb) / std::max({std::fabs(ta), std::fabs(tb), 1e-30});
        r.max_relative_error = std::max(r.max_relative_error, rel);
        if (rel <= rel_tol) ++r.agreeing;
    }
    return r;
}

Image split_view(const Frame& raster, const Frame& ray, const WorkSummary& work) {
    const int w = ray.width, h = ray.height;
    Image out(2 * w, h, kBackground);
    blit(out, raster.colour, 0, 0);
    blit(out, ray.colour, w, 0);
    fill_rect(out, w - 1, 0, 2, h, {255, 255, 255});  // the divider
    const int s = label_scale(h);
    const int pad = 4 * s;
    draw_label(out, pad, pad, "Rasterized (z-buffer)", s + 1, w - 2 * pad);
    draw_label(out, w + pad, pad, "Ray cast (" + work.accel_name + ")", s + 1, w - 2 * pad);
    const RasterStats& rs = work.raster_work;
    const uint64_t rays = uint64_t(w) * h;
    std::string ray_text = with_commas(rays) + " rays";
    if (work.ray_work_counted)
        ray_text += ", " + with_commas(work.ray_work.box_tests) + " box tests, " +
                    with_commas(work.ray_work.triangle_tests) + " triangle tests";
    const DepthAgreement agree = compare_depths(raster, ray);
    // Two lines at the bottom of each half, stacked up from its bottom edge; the
    // verdict concerns both halves, a line under each.
    auto bottom_lines = [&](int x, const std::string& upper, const std::string& lower) {
        const int gap = s;
        const int lower_y = h - pad - label_height(out, x, lower, s, w - 2 * pad);
        draw_label(out, x, lower_y, lower, s, w - 2 * pad);
        draw_label(out, x, lower_y - gap - label_height(out, x, upper, s, w - 2 * pad), upper, s, w - 2 * pad);
    };
    bottom_lines(pad,
                 with_commas(rs.triangles_rasterized) + " triangles rasterized, " + with_commas(rs.fragments) +
                     " fragments",
                 fmt("depths agree on %.3f%% of shared pixels (1e-4 rel.)", agree.agreeing_percent()));
    bottom_lines(w + pad, ray_text, fmt("coverage differs on %.3f%% of pixels", agree.coverage_differs_percent()));
    return out;
}

Image depth_diff_colours(const Frame& raster, const Frame& ray, double rel_tol) {
    const int w = ray.width, h = ray.height;
    Image out(w, h, kBackground);
    // Depth range of the shared pixels, for the grey shading of agreeing pixels.
    float t_near = kInfinity, t_far = 0;
    for (size_t i = 0; i < ray.depth.size(); ++i)
        if (std::isfinite(ray.depth[i])) { t_near = std::min(t_near, ray.depth[i]); t_far = std::max(t_far, ray.depth[i]); }
    // Relative errors from rel_tol (just visible) to 1e3 * rel_tol (saturated), on a log scale.
    const double log_lo = std::log10(rel_tol), log_hi = log_lo + 3;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t i = ray.index(x, y);
            const bool hr = std::isfinite(raster.depth[i]), hc = std::isfinite(ray.depth[i]);
            Rgb& p = out.at(x, y);
            if (hr && !hc) { p = {230, 40, 200}; continue; }
            if (!hr && hc) { p = {40, 220, 230}; continue; }
            if (!hr) continue;
            const double ta = raster.depth[i], tb = ray.depth[i];
            const double rel = std::fabs(ta - tb) / std::max(std::fabs(tb), 1e-30);
            if (rel <= rel_tol) {
                const float f = t_far > t_near ? (ray.depth[i] - t_near) / (t_far - t_near) : 0.0f;
                const auto g = uint8_t(std::lround(200 - 130 * f));
                p = {g, g, g};
            } else {
                p = colormap((std::log10(rel) - log_lo) / (log_hi - log_lo));
            }
        }
    return out;
}

std::array<std::string, 3> depth_diff_ticks(double rel_tol) {
    return {fmt("%.0e", rel_tol), fmt("%.0e", rel_tol * 31.6), fmt("%.0e", rel_tol * 1e3)};
}

Image depth_diff_view(const Frame& raster, const Frame& ray, double rel_tol) {
    Image out = depth_diff_colours(raster, ray, rel_tol);
    const int w = out.width, h = out.height;
    const int s = label_scale(h);
    const DepthAgreement agree = compare_depths(raster, ray, rel_tol);
    int y = 4 * s;
    y += draw_label(out, 4 * s, y, "Depth difference: rasterizer vs ray caster", s + 1) + s;
    y += draw_label(out, 4 * s, y,
                    fmt("grey: agree within %.0e relative (", rel_tol) +
                        fmt("%.3f%% of shared pixels)", agree.agreeing_percent()),
                    s) + s;
    draw_label(out, 4 * s, y,
               "magenta: raster only, cyan: ray cast only (" + fmt("%.3f%% of pixels)", agree.coverage_differs_percent()),
               s);
    const int bar_w = std::min(w / 3, 300 * s);
    draw_legend_bar(out, w - bar_w - 8 * s, h - 22 * s, bar_w, 6 * s, "relative depth error (log scale)",
                    depth_diff_ticks(rel_tol));
    return out;
}

Image depth_grey_view(const Frame& frame, float t_near, float t_far) {
    Image out(frame.width, frame.height, {0, 0, 0});
    for (size_t i = 0; i < frame.depth.size(); ++i) {
        const float t = frame.depth[i];
        if (!std::isfinite(t)) continue;
        const float f = t_far > t_near ? std::clamp((t - t_near) / (t_far - t_near), 0.0f, 1.0f) : 0.0f;
        const auto g = uint8_t(std::lround(255 - 200 * f));
        out.pixels[i] = {g, g, g};
    }
    return out;
}

HeatScale heat_scale(const std::vector<uint32_t>& counts, double max_value) {
    HeatScale scale;
    uint64_t sum = 0;
    uint32_t largest = 0;
    for (uint32_t c : counts) {
        sum += c;
        largest = std::max(largest, c);
    }
    scale.max_value = max_value > 0 ? max_value : std::max<uint32_t>(largest, 1);
    scale.mean = counts.empty() ? 0.0 : double(sum) / double(counts.size());
    scale.ticks = {count_label(0), count_label(scale.max_value / 2), count_label(scale.max_value)};
    return scale;
}

Image heat_colours(const std::vector<uint32_t>& counts, int width, int height, const HeatScale& scale) {
    Image out(width, height);
    for (size_t i = 0; i < counts.size() && i < out.pixels.size(); ++i)
        out.pixels[i] = colormap(counts[i] / scale.max_value);
    return out;
}

Image heat_view(const std::vector<uint32_t>& counts, int width, int height, const std::string& title,
                double max_value) {
    const HeatScale scale = heat_scale(counts, max_value);
    Image out = heat_colours(counts, width, height, scale);
    const int s = label_scale(height);
    const int y = 4 * s + draw_label(out, 4 * s, 4 * s, title, s + 1) + s;
    draw_label(out, 4 * s, y, fmt("mean %.1f per pixel", scale.mean), s);
    const int bar_w = std::min(width / 3, 300 * s);
    draw_legend_bar(out, width - bar_w - 8 * s, height - 22 * s, bar_w, 6 * s, "count per pixel", scale.ticks);
    return out;
}

}  // namespace accelviz
