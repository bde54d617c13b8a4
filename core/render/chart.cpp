#include "core/render/chart.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace accelviz {

namespace {

std::string tick_text(double v) {
    char text[32];
    std::snprintf(text, sizeof text, std::abs(v) >= 100 || v == std::floor(v) ? "%.0f" : "%.3g", v);
    return text;
}

/// A round step giving about `count` ticks over [0, hi].
double tick_step(double hi, int count) {
    const double raw = hi / std::max(1, count);
    const double power = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
        if (m * power >= raw) return m * power;
    return 10.0 * power;
}

}  // namespace

void draw_line_chart(Image& dst, int x0, int y0, int w, int h, const LineChart& chart) {
    const Rgb background{250, 250, 247}, ink{40, 40, 40}, grid{215, 215, 210};
    fill_rect(dst, x0, y0, w, h, background);
    const int s = std::max(1, h / 240);
    int text_w = 0, text_h = 0;
    text_size("0", s, &text_w, &text_h);
    // The plot area: room for the title above, tick labels left and below, the legend right.
    int legend_w = 0;
    for (const ChartSeries& series : chart.series) {
        int sw = 0, sh = 0;
        text_size(series.name, s, &sw, &sh);
        legend_w = std::max(legend_w, sw);
    }
    legend_w += 24 * s;
    const int left = x0 + 8 * s + 6 * text_w, right = x0 + w - legend_w - 8 * s;
    const int top = y0 + 3 * text_h + 4 * s, bottom = y0 + h - 3 * text_h - 4 * s;
    if (right - left < 20 || bottom - top < 20) return;
    draw_text(dst, x0 + 6 * s, y0 + 3 * s, chart.title, s + (h >= 300 ? 1 : 0), ink);

    double x_lo = 0, x_hi = 0, y_hi = 0;
    bool any = false;
    for (const ChartSeries& series : chart.series)
        for (size_t i = 0; i < series.x.size() && i < series.y.size(); ++i) {
            if (!std::isfinite(series.x[i]) || !std::isfinite(series.y[i])) continue;
            x_lo = any ? std::min(x_lo, series.x[i]) : series.x[i];
            x_hi = any ? std::max(x_hi, series.x[i]) : series.x[i];
            y_hi = std::max(y_hi, series.y[i]);
            any = true;
        }
    if (!any) return;
    if (!(x_hi > x_lo)) x_hi = x_lo + 1;
    if (!(y_hi > 0)) y_hi = 1;
    const double y_step = tick_step(y_hi, 4);
    y_hi = std::ceil(y_hi / y_step) * y_step;
    auto px = [&](double x) { return left + (x - x_lo) / (x_hi - x_lo) * (right - left); };
    auto py = [&](double y) { return bottom - y / y_hi * (bottom - top); };

    // Grid lines and ticks.
    for (double y = 0; y <= y_hi * (1 + 1e-9) && y <= 50 * y_step; y += y_step) {
        draw_line(dst, left, py(y), right, py(y), grid);
        const std::string label = tick_text(y);
        int lw = 0, lh = 0;
        text_size(label, s, &lw, &lh);
        draw_text(dst, left - lw - 4 * s, int(py(y)) - lh / 2, label, s, ink);
    }
    const double x_step = tick_step(x_hi - x_lo, 8);
    int ticks = 0;
    for (double x = std::ceil(x_lo / x_step) * x_step; x <= x_hi * (1 + 1e-9) + 1e-12 && ticks < 50; x += x_step, ++ticks) {
        draw_line(dst, px(x), top, px(x), bottom, grid);
        const std::string label = tick_text(x);
        int lw = 0, lh = 0;
        text_size(label, s, &lw, &lh);
        draw_text(dst, int(px(x)) - lw / 2, bottom + 3 * s, label, s, ink);
    }
    draw_line(dst, left, bottom, right, bottom, ink, s);
    draw_line(dst, left, top, left, bottom, ink, s);
    int lw = 0, lh = 0;
    text_size(chart.x_label, s, &lw, &lh);
    draw_text(dst, (left + right - lw) / 2, bottom + 4 * s + text_h, chart.x_label, s, ink);
    draw_text(dst, left, top - text_h - 2 * s, chart.y_label, s, ink);

    if (chart.mark_x && *chart.mark_x >= x_lo && *chart.mark_x <= x_hi) {
        const double x = px(*chart.mark_x);
        for (int y = top; y < bottom; y += 6 * s) draw_line(dst, x, y, x, std::min(bottom, y + 3 * s), {200, 60, 60}, s);
        draw_text(dst, int(x) + 4 * s, top + 2 * s, chart.mark_label, s, {200, 60, 60});
    }
    // The series, then the legend.
    int legend_y = top;
    for (const ChartSeries& series : chart.series) {
        auto finite = [&](size_t i) { return std::isfinite(series.x[i]) && std::isfinite(series.y[i]); };
        for (size_t i = 0; i + 1 < series.x.size() && i + 1 < series.y.size(); ++i)
            if (finite(i) && finite(i + 1))
                draw_line(dst, px(series.x[i]), py(series.y[i]), px(series.x[i + 1]), py(series.y[i + 1]),
                          series.colour, 2 * s);
        for (size_t i = 0; i < series.x.size() && i < series.y.size(); ++i)
            if (finite(i))
                fill_rect(dst, int(px(series.x[i])) - 2 * s, int(py(series.y[i])) - 2 * s, 5 * s, 5 * s, series.colour);
        fill_rect(dst, right + 8 * s, legend_y + text_h / 2 - s, 12 * s, 3 * s, series.colour);
        draw_text(dst, right + 22 * s, legend_y, series.name, s, ink);
        legend_y += text_h + 4 * s;
    }
}

}  // namespace accelviz
