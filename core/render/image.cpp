#include "core/render/image.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>

#include <stb/stb_image.h>
#include <stb/stb_image_write.h>

// stb_easy_font is a small header-only font (a Debian package header); it is
// not compiled into libstb, so this file is its one implementation unit.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop
#include <stb/stb_truetype.h>  // compiled into Debian's libstb

namespace accelviz {

std::optional<Error> write_png(const Image& image, const std::string& path) {
    if (image.width <= 0 || image.height <= 0) return Error{path + ": cannot write an empty image"};
    const int ok = stbi_write_png(path.c_str(), image.width, image.height, 3, image.pixels.data(),
                                  image.width * 3);
    if (!ok) return Error{path + ": cannot write PNG (does the directory exist and is it writable?)"};
    return std::nullopt;
}

Expected<Image> read_png(const std::string& path) {
    int w = 0, h = 0, n = 0;
    std::unique_ptr<unsigned char, void (*)(void*)> data(stbi_load(path.c_str(), &w, &h, &n, 3),
                                                        stbi_image_free);
    if (!data) return Error{path + ": cannot read PNG (" + (stbi_failure_reason() ? stbi_failure_reason() : "unknown") + ")"};
    Image img(w, h);
    std::memcpy(img.pixels.data(), data.get(), size_t(w) * h * 3);
    return img;
}

std::optional<Error> write_pfm(const std::vector<float>& depth, int width, int height,
                               const std::string& path) {
    static_assert(std::endian::native == std::endian::little, "PFM writer assumes a little-endian host");
    std::ofstream out(path, std::ios::binary);
    if (!out) return Error{path + ": cannot open for writing"};
    out << "Pf\n" << width << " " << height << "\n-1.0\n";
    for (int y = height - 1; y >= 0; --y)  // PFM rows run bottom to top
        out.write(reinterpret_cast<const char*>(depth.data() + size_t(y) * width),
                  std::streamsize(sizeof(float) * width));
    if (!out) return Error{path + ": write failed"};
    return std::nullopt;
}

Expected<std::vector<float>> read_pfm(const std::string& path, int* width, int* height) {
    std::ifstream in(path, std::ios::binary);
    if (!in) return Error{path + ": cannot open"};
    std::string magic;
    int w = 0, h = 0;
    double scale = 0;
    in >> magic >> w >> h >> scale;
    if (magic != "Pf" || w <= 0 || h <= 0 || scale >= 0) return Error{path + ": not a little-endian greyscale PFM"};
    in.get();  // the single whitespace after the header
    std::vector<float> rows(size_t(w) * h);
    in.read(reinterpret_cast<char*>(rows.data()), std::streamsize(rows.size() * sizeof(float)));
    if (!in) return Error{path + ": truncated PFM"};
    std::vector<float> top_down(rows.size());
    for (int y = 0; y < h; ++y)
        std::memcpy(&top_down[size_t(y) * w], &rows[size_t(h - 1 - y) * w], sizeof(float) * w);
    *width = w;
    *height = h;
    return top_down;
}

void blit(Image& dst, const Image& src, int x0, int y0) {
    for (int y = 0; y < src.height; ++y)
        for (int x = 0; x < src.width; ++x)
            if (dst.inside(x0 + x, y0 + y)) dst.at(x0 + x, y0 + y) = src.at(x, y);
}

void fill_rect(Image& dst, int x0, int y0, int w, int h, Rgb colour) {
    const int xa = std::max(0, x0), ya = std::max(0, y0);
    const int xb = std::min(dst.width, x0 + w), yb = std::min(dst.height, y0 + h);
    for (int y = ya; y < yb; ++y)
        for (int x = xa; x < xb; ++x) dst.at(x, y) = colour;
}

void draw_line(Image& dst, double x0, double y0, double x1, double y1, Rgb colour, int thickness) {
    // One square dab per pixel step along the longer axis.
    const double steps = std::max({std::abs(x1 - x0), std::abs(y1 - y0), 1.0});
    if (!(steps < 1e5)) return;  // not finite, or far off the image
    const int half = thickness / 2;
    for (int k = 0; k <= int(steps); ++k) {
        const double f = double(k) / steps;
        fill_rect(dst, int(std::lround(x0 + f * (x1 - x0))) - half, int(std::lround(y0 + f * (y1 - y0))) - half,
                  thickness, thickness, colour);
    }
}

namespace {

/// The labels' font (kDejaVuSansPath), read once.
class LabelFont {
public:
    static const LabelFont& get() {
        static const LabelFont font;  // loaded once, then only read (safe from any thread)
        return font;
    }
    bool loaded() const { return loaded_; }
    const stbtt_fontinfo& info() const { return info_; }

private:
    LabelFont() {
        std::ifstream in(kDejaVuSansPath, std::ios::binary);
        data_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        loaded_ = !data_.empty() &&
                  stbtt_InitFont(&info_, data_.data(), stbtt_GetFontOffsetForIndex(data_.data(), 0)) != 0;
    }
    std::vector<unsigned char> data_;
    stbtt_fontinfo info_{};
    bool loaded_ = false;
};

/// The next code point of UTF-8 `text` at `i` (advanced past it); a stray byte reads as itself.
int next_code_point(std::string_view text, size_t& i) {
    const auto byte = [&](size_t k) { return k < text.size() ? uint8_t(text[k]) : uint8_t(0); };
    const uint8_t c = byte(i);
    int length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 1;
    int cp = length == 1 ? c : c & (0xFF >> (length + 1));
    for (int k = 1; k < length; ++k) {
        if ((byte(i + size_t(k)) & 0xC0) != 0x80) {
            length = 1;
            cp = c;
            break;
        }
        cp = (cp << 6) | (byte(i + size_t(k)) & 0x3F);
    }
    i += size_t(length);
    return cp;
}

/// Lays out one line of `text` at `line_px` pixels: calls glyph(code point, pen x,
/// font scale) for each character; returns the line's width.
template <class Glyph>
float lay_out(const stbtt_fontinfo& font, std::string_view text, float line_px, Glyph&& glyph) {
    const float s = stbtt_ScaleForPixelHeight(&font, line_px);
    float pen = 0;
    int previous = 0;
    for (size_t i = 0; i < text.size();) {
        const int cp = next_code_point(text, i);
        if (previous) pen += s * float(stbtt_GetCodepointKernAdvance(&font, previous, cp));
        glyph(cp, pen, s);
        int advance = 0, bearing = 0;
        stbtt_GetCodepointHMetrics(&font, cp, &advance, &bearing);
        pen += s * float(advance);
        previous = cp;
    }
    return pen;
}

constexpr int kLinePixels = 12;  ///< a line's height at scale 1 (stb_easy_font's too)

/// draw_text without the font file: stb_easy_font's stroke glyphs (ASCII).
void draw_text_strokes(Image& dst, int x, int y, std::string_view text, int scale, Rgb colour) {
    std::string s(text);
    // Each glyph stroke is a quad of 4 vertices, 16 bytes each (x, y, z, colour).
    std::vector<char> buffer(s.size() * 270 + 1024);
    const int quads = stb_easy_font_print(0, 0, s.data(), nullptr, buffer.data(), int(buffer.size()));
    for (int q = 0; q < quads; ++q) {
        const float* v = reinterpret_cast<const float*>(buffer.data() + q * 64);
        // vertices 0 and 2 are opposite corners of an axis-aligned quad
        const float qx0 = std::min(v[0], v[8]), qx1 = std::max(v[0], v[8]);
        const float qy0 = std::min(v[1], v[9]), qy1 = std::max(v[1], v[9]);
        fill_rect(dst, x + int(std::lround(qx0 * scale)), y + int(std::lround(qy0 * scale)),
                  int(std::lround((qx1 - qx0) * scale)), int(std::lround((qy1 - qy0) * scale)), colour);
    }
}


}  // namespace

void text_size(std::string_view text, int scale, int* width, int* height) {
    const LabelFont& font = LabelFont::get();
    if (!font.loaded()) {
        std::string s(text);
        *width = stb_easy_font_width(s.data()) * scale;
        *height = stb_easy_font_height(s.data()) * scale;
        return;
    }
    *width = int(std::ceil(lay_out(font.info(), text, float(kLinePixels * scale), [](int, float, float) {})));
    *height = kLinePixels * scale;
}

void draw_text(Image& dst, int x, int y, std::string_view text, int scale, Rgb colour) {
    const LabelFont& font = LabelFont::get();
    if (!font.loaded()) return draw_text_strokes(dst, x, y, text, scale, colour);
    const stbtt_fontinfo& info = font.info();
    const float line_px = float(kLinePixels * scale);
    int ascent = 0, descent = 0, gap = 0;
    stbtt_GetFontVMetrics(&info, &ascent, &descent, &gap);
    const int baseline = y + int(std::lround(float(ascent) * stbtt_ScaleForPixelHeight(&info, line_px)));
    std::vector<unsigned char> coverage;
    lay_out(info, text, line_px, [&](int cp, float pen, float s) {
        const float shift = pen - std::floor(pen);
        int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
        stbtt_GetCodepointBitmapBoxSubpixel(&info, cp, s, s, shift, 0, &x0, &y0, &x1, &y1);
        const int w = x1 - x0, h = y1 - y0;
        if (w <= 0 || h <= 0) return;
        coverage.assign(size_t(w) * size_t(h), 0);
        stbtt_MakeCodepointBitmapSubpixel(&info, coverage.data(), w, h, w, s, s, shift, 0, cp);
        const int left = x + int(std::floor(pen)) + x0, top = baseline + y0;
        for (int gy = 0; gy < h; ++gy)
            for (int gx = 0; gx < w; ++gx) {
                const int px = left + gx, py = top + gy;
                const int a = coverage[size_t(gy) * size_t(w) + size_t(gx)];
                if (a == 0 || px < 0 || py < 0 || px >= dst.width || py >= dst.height) continue;
                Rgb& p = dst.at(px, py);
                const auto mix = [a](uint8_t under, uint8_t over) { return uint8_t((under * (255 - a) + over * a + 127) / 255); };
                p = {mix(p.r, colour.r), mix(p.g, colour.g), mix(p.b, colour.b)};
            }
    });
}

namespace {

/// The scale a label is drawn at: `scale`, shrunk (down to 1) until it fits in max_width.
int fitted_scale(const Image& dst, int x, std::string_view text, int scale, int max_width, int* w, int* h) {
    if (max_width <= 0) max_width = dst.width - x;
    text_size(text, scale, w, h);
    while (scale > 1 && *w + 4 * scale > max_width) text_size(text, --scale, w, h);
    return scale;
}

}  // namespace

int label_height(const Image& dst, int x, std::string_view text, int scale, int max_width) {
    int w = 0, h = 0;
    scale = fitted_scale(dst, x, text, scale, max_width, &w, &h);
    return h + 4 * scale;
}

int draw_label(Image& dst, int x, int y, std::string_view text, int scale, int max_width) {
    int w = 0, h = 0;
    scale = fitted_scale(dst, x, text, scale, max_width, &w, &h);
    const int pad = 2 * scale;
    for (int yy = std::max(0, y); yy < std::min(dst.height, y + h + 2 * pad); ++yy)
        for (int xx = std::max(0, x); xx < std::min(dst.width, x + w + 2 * pad); ++xx) {
            Rgb& p = dst.at(xx, yy);  // darken to 30% so the label reads on any background
            p = {uint8_t(p.r * 3 / 10), uint8_t(p.g * 3 / 10), uint8_t(p.b * 3 / 10)};
        }
    draw_text(dst, x + pad, y + pad, text, scale, {255, 255, 255});
    return h + 2 * pad;
}

}  // namespace accelviz
