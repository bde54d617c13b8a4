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

/// A decade's label: 0.01, 0.1, 1, 10, 100, 1k, 10k, 100k, 1M, 10M, ...
std::string decade_text(int power) {
    static const char* const kBig[] = {"1", "10", "100", "1k", "10k", "100k", "1M", "10M", "100M", "1G"};
    if (power >= 0 && power < 10) return kBig[power];
    char text[32];
    std::snprintf(text, sizeof text, "%g", std::pow(10.0, power));
    return text;
}

}  // namespace

void draw_line_chart(Image& dst, int x0, int y0, int w, int h, const LineChart& chart) {
    const Rgb background{250, 250, 247}, ink{40, 40, 40}, grid{215, 215, 210};
    fill_rect(dst, x0, y0, w, h, background);
    const int s = chart.text_scale > 0 ? chart.text_scale : std::max(1, h / 240);
    int text_w = 0, text_h = 0;
    text_size("0", s, &text_w, &text_h);
    // The plot area: room for the title above, tick labels left and below, the legend right.
    int legend_w = 0;
    for (const ChartSeries& series : chart.series) {
        if (!chart.legend) break;
        int sw = 0, sh = 0;
        text_size(series.name, s, &sw, &sh);
        legend_w = std::max(legend_w, sw);
    }
    if (chart.legend) legend_w += 24 * s;
    // (Without a legend, room for half the last tick label; without a title, for the y label only.)
    const int left = x0 + 8 * s + 6 * text_w, right = x0 + w - legend_w - 8 * s - (chart.legend ? 0 : 2 * text_w);
    const int top = y0 + (chart.title.empty() ? 2 * text_h : 3 * text_h) + 4 * s, bottom = y0 + h - 3 * text_h - 4 * s;
    if (right - left < 20 || bottom - top < 20) return;
    if (!chart.title.empty()) draw_text(dst, x0 + 6 * s, y0 + 3 * s, chart.title, s + (h >= 300 ? 1 : 0), ink);

    // Data coordinates: x and y as given, or their log10 (log_log).
    const auto usable = [&](double x, double y) {
        return std::isfinite(x) && std::isfinite(y) && (!chart.log_log || (x > 0 && y > 0));
    };
    const auto to_x = [&](double x) { return chart.log_log ? std::log10(x) : x; };
    const auto to_y = [&](double y) { return chart.log_log ? std::log10(y) : y; };
    double x_lo = 0, x_hi = 0, y_lo = 0, y_hi = 0;
    bool any = false;
    for (const ChartSeries& series : chart.series)
        for (size_t i = 0; i < series.x.size() && i < series.y.size(); ++i) {
            if (!usable(series.x[i], series.y[i])) continue;
            const double x = to_x(series.x[i]), y = to_y(series.y[i]);
            x_lo = any ? std::min(x_lo, x) : x;
            x_hi = any ? std::max(x_hi, x) : x;
            y_lo = any ? std::min(y_lo, y) : y;
            y_hi = any ? std::max(y_hi, y) : y;
            any = true;
        }
    if (!any) return;
    if (chart.log_log) {  // whole decades, at least one each way
        x_lo = std::floor(x_lo);
        x_hi = std::max(std::ceil(x_hi), x_lo + 1);
        y_lo = std::floor(y_lo);
        y_hi = std::max(std::ceil(y_hi), y_lo + 1);
    } else {
        y_lo = 0;
        if (!(x_hi > x_lo)) x_hi = x_lo + 1;
        if (!(y_hi > 0)) y_hi = 1;
    }
    const double y_step = chart.log_log ? 1.0 : tick_step(y_hi, 4);
    y_hi = chart.log_log ? y_hi : std::ceil(y_hi / y_step) * y_step;
    auto px = [&](double x) { return left + (x - x_lo) / (x_hi - x_lo) * (right - left); };
    auto py = [&](double y) { return bottom - (y - y_lo) / (y_hi - y_lo) * (bottom - top); };

    // Grid lines and ticks (log_log: a line per decade, fainter ones at 2 and 5 times it).
    const auto label_y = [&](double y, const std::string& label) {
        int lw = 0, lh = 0;
        text_size(label, s, &lw, &lh);
        draw_text(dst, left - lw - 4 * s, int(py(y)) - lh / 2, label, s, ink);
    };
    const auto label_x = [&](double x, const std::string& label) {
        int lw = 0, lh = 0;
        text_size(label, s, &lw, &lh);
        draw_text(dst, int(px(x)) - lw / 2, bottom + 3 * s, label, s, ink);
    };
    if (chart.log_log) {
        const Rgb faint{235, 235, 230};
        // Every k-th decade labelled when the labels would crowd (wide ranges, small charts).
        int label_w = 0, label_h = 0;
        text_size("100M", s, &label_w, &label_h);
        const auto label_step = [](double decades, int label, int length) {
            return std::max(1, int(std::ceil(decades * label / std::max(1, length))));
        };
        const int y_every = label_step(y_hi - y_lo, label_h + 2 * s, bottom - top);
        const int x_every = label_step(x_hi - x_lo, label_w + 4 * s, right - left);
        for (int d = int(y_lo); d <= int(y_hi); ++d) {
            for (double m : {2.0, 5.0})
                if (const double y = d + std::log10(m); y < y_hi) draw_line(dst, left, py(y), right, py(y), faint);
            draw_line(dst, left, py(d), right, py(d), grid);
            if ((d - int(y_lo)) % y_every == 0) label_y(d, decade_text(d));
        }
        for (int d = int(x_lo); d <= int(x_hi); ++d) {
            for (double m : {2.0, 5.0})
                if (const double x = d + std::log10(m); x < x_hi) draw_line(dst, px(x), top, px(x), bottom, faint);
            draw_line(dst, px(d), top, px(d), bottom, grid);
            if ((d - int(x_lo)) % x_every == 0) label_x(d, decade_text(d));
        }
    } else {
        for (double y = 0; y <= y_hi * (1 + 1e-9) && y <= 50 * y_step; y += y_step) {
            draw_line(dst, left, py(y), right, py(y), grid);
            label_y(y, tick_text(y));
        }
        const double x_step = tick_step(x_hi - x_lo, 8);
        int ticks = 0;
        for (double x = std::ceil(x_lo / x_step) * x_step; x <= x_hi * (1 + 1e-9) + 1e-12 && ticks < 50;
             x += x_step, ++ticks) {
            draw_line(dst, px(x), top, px(x), bottom, grid);
            label_x(x, tick_text(x));
        }
    }
    draw_line(dst, left, bottom, right, bottom, ink, s);
    draw_line(dst, left, top, left, bottom, ink, s);
    int lw = 0, lh = 0;
    text_size(chart.x_label, s, &lw, &lh);
    draw_text(dst, (left + right - lw) / 2, bottom + 4 * s + text_h, chart.x_label, s, ink);
    draw_text(dst, left, top - text_h - 2 * s, chart.y_label, s, ink);

    if (chart.mark_x && usable(*chart.mark_x, 1.0) && to_x(*chart.mark_x) >= x_lo && to_x(*chart.mark_x) <= x_hi) {
        const double x = px(to_x(*chart.mark_x));
        for (int y = top; y < bottom; y += 6 * s) draw_line(dst, x, y, x, std::min(bottom, y + 3 * s), {200, 60, 60}, s);
        draw_text(dst, int(x) + 4 * s, top + 2 * s, chart.mark_label, s, {200, 60, 60});
    }
    // The series, then the legend.
    int legend_y = top;
    for (const ChartSeries& series : chart.series) {
        auto finite = [&](size_t i) { return usable(series.x[i], series.y[i]); };
        auto sx = [&](size_t i) { return px(to_x(series.x[i])); };
        auto sy = [&](size_t i) { return py(to_y(series.y[i])); };
        for (size_t i = 0; i + 1 < series.x.size() && i + 1 < series.y.size(); ++i)
            if (finite(i) && finite(i + 1)) draw_line(dst, sx(i), sy(i), sx(i + 1), sy(i + 1), series.colour, 2 * s);
        for (size_t i = 0; i < series.x.size() && i < series.y.size(); ++i)
            if (finite(i)) fill_rect(dst, int(sx(i)) - 2 * s, int(sy(i)) - 2 * s, 5 * s, 5 * s, series.colour);
        if (!chart.legend) continue;
        fill_rect(dst, right + 8 * s, legend_y + text_h / 2 - s, 12 * s, 3 * s, series.colour);
        draw_text(dst, right + 22 * s, legend_y, series.name, s, ink);
        legend_y += text_h + 4 * s;
    }
}

}  // namespace accelviz
