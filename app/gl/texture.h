#pragma once
/// A 2D texture holding an image: CPU-rendered views (ray cast, raster, heat
/// maps) shown in the window, and the ImGui font atlas.

#include "app/gl/gl_objects.h"
#include "core/render/image.h"

namespace accelviz {

class Texture {
public:
    /// Uploads an RGB image (top row first, so texture v = 0 is the image's top).
    /// `smooth`: linear filtering when scaled; otherwise nearest (pixels stay crisp).
    void upload(const Image& image, bool smooth = false);
    /// Uploads tightly packed RGBA8 pixels.
    void upload_rgba(const unsigned char* pixels, int width, int height, bool smooth);
    /// Uploads one float per pixel (top row first; a depth image), never filtered.
    void upload_floats(const float* values, int width, int height);
    /// Copies a rectangle of the frame being drawn (GL's bottom-up rows from `gl_y`)
    /// without a trip through the CPU: its colours (RGB), or its depth buffer's values
    /// (`Content::Depth`, read by a shader's sampler as depth-buffer values), never filtered.
    enum class Content { Colour, Depth };
    void copy_from_frame(Content content, int x, int gl_y, int width, int height);

    /// Rows stored bottom row first (copied from the frame), not top row first
    /// (uploaded): whoever draws the texture flips it back.
    bool bottom_up() const { return bottom_up_; }

    GLuint id() const { return texture_.id(); }
    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return width_ == 0 || height_ == 0; }

private:
    void upload_pixels(GLenum format, const void* pixels, int width, int height, bool smooth);
    GlTexture texture_;
    int width_ = 0, height_ = 0;
    bool bottom_up_ = false;
    bool holds_depth_ = false;  ///< copied from the depth buffer
};

}  // namespace accelviz
