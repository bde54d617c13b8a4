#pragma once
/// Plain images the core hands to the CLI and the window: 8-bit RGB colour and
/// float depth. Rows are stored top to bottom (y = 0 is the top row).

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/util/expected.h"

namespace accelviz {

struct Rgb {
    uint8_t r = 0, g = 0, b = 0;
    bool operator==(const Rgb&) const = default;
};

struct Image {
    int width = 0, height = 0;
    std::vector<Rgb> pixels;  ///< width * height, row-major, top row first

    Image() = default;
    Image(int w, int h, Rgb fill = {}) : width(w), height(h), pixels(size_t(w) * h, fill) {}
    Rgb& at(int x, int y) { return pixels[size_t(y) * width + x]; }
    const Rgb& at(int x, int y) const { return pixels[size_t(y) * width + x]; }
    bool inside(int x, int y) const { return x >= 0 && y >= 0 && x < width && y < height; }
};

/// Writes an 8-bit RGB PNG. Returns an error naming the file on failure.
std::optional<Error> write_png(const Image& image, const std::string& path);
/// Reads a PNG as 8-bit RGB (for golden-image tests).
Expected<Image> read_png(const std::string& path);

/// Writes a PFM depth image: header "Pf", "W H", "-1.0" (little-endian), then W*H
/// float32 in rows from BOTTOM to top; +inf where nothing is hit.
std::optional<Error> write_pfm(const std::vector<float>& depth, int width, int height,
                               const std::string& path);
/// Reads a PFM written by write_pfm (rows returned top to bottom).
Expected<std::vector<float>> read_pfm(const std::string& path, int* width, int* height);

/// Copies `src` into `dst` with its top-left corner at (x0, y0), clipped.
void blit(Image& dst, const Image& src, int x0, int y0);
/// Fills a rectangle (clipped).
void fill_rect(Image& dst, int x0, int y0, int w, int h, Rgb colour);
/// A straight line from (x0, y0) to (x1, y1), `thickness` pixels wide (clipped).
void draw_line(Image& dst, double x0, double y0, double x1, double y1, Rgb colour, int thickness = 1);
/// DejaVu Sans (Debian's fonts-dejavu-core): the font of the window's panels and of
/// the text drawn into images, so the two read alike.
inline constexpr const char* kDejaVuSansPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Draws text (UTF-8) with its top-left at (x, y), one line 12 · `scale` pixels
/// tall. Set in DejaVu Sans, the window's own font (Debian's fonts-dejavu-core,
/// rasterized by stb_truetype, anti-aliased); where that file is missing, in
/// stb_easy_font's built-in strokes (ASCII only).
void draw_text(Image& dst, int x, int y, std::string_view text, int scale, Rgb colour);
/// Width and height in pixels that draw_text would cover.
void text_size(std::string_view text, int scale, int* width, int* height);
/// Text on a translucent dark box, for labels over images. The scale shrinks (down
/// to 1) until the label fits in `max_width` pixels (0: up to the image's right edge).
/// Returns the box's height, so the next label can go right under it.
int draw_label(Image& dst, int x, int y, std::string_view text, int scale, int max_width = 0);
/// The height of the box draw_label would draw (to stack labels up from a bottom edge).
int label_height(const Image& dst, int x, std::string_view text, int scale, int max_width = 0);

}  // namespace accelviz
