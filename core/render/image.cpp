#include "core/render/image.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
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

void text_size(std::string_view text, int scale, int* width, int* height) {
    std::string s(text);
    *width = stb_easy_font_width(s.data()) * scale;
    *height = stb_easy_font_height(s.data()) * scale;
}

void draw_text(Image& dst, int x, int y, std::string_view text, int scale, Rgb colour) {
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

void draw_label(Image& dst, int x, int y, std::string_view text, int scale, int max_width) {
    if (max_width <= 0) max_width = dst.width - x;
    int w = 0, h = 0;
    text_size(text, scale, &w, &h);
    while (scale > 1 && w + 4 * scale > max_width) text_size(text, --scale, &w, &h);  // shrink to fit
    const int pad = 2 * scale;
    for (int yy = std::max(0, y); yy < std::min(dst.height, y + h + 2 * pad); ++yy)
        for (int xx = std::max(0, x); xx < std::min(dst.width, x + w + 2 * pad); ++xx) {
            Rgb& p = dst.at(xx, yy);  // darken to 30% so the label reads on any background
            p = {uint8_t(p.r * 3 / 10), uint8_t(p.g * 3 / 10), uint8_t(p.b * 3 / 10)};
        }
    draw_text(dst, x + pad, y + pad, text, scale, {255, 255, 255});
}

}  // namespace accelviz
