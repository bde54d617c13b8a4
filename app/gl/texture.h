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

    GLuint id() const { return texture_.id(); }
    int width() const { return width_; }
    int height() const { return height_; }
    bool empty() const { return width_ == 0 || height_ == 0; }

private:
    void upload_pixels(GLenum format, const void* pixels, int width, int height, bool smooth);
    GlTexture texture_;
    int width_ = 0, height_ = 0;
};

}  // namespace accelviz
