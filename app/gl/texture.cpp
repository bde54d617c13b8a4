#include "app/gl/texture.h"

namespace accelviz {

void Texture::upload(const Image& image, bool smooth) {
    upload_pixels(GL_RGB, image.pixels.data(), image.width, image.height, smooth);
}

void Texture::upload_rgba(const unsigned char* pixels, int width, int height, bool smooth) {
    upload_pixels(GL_RGBA, pixels, width, height, smooth);
}

void Texture::upload_floats(const float* values, int width, int height) {
    upload_pixels(GL_RED, values, width, height, false);
}

namespace {

/// Binds the texture and sets its sampling: filtered when smooth, clamped at the edges.
void bind_with_filter(GLuint texture, bool smooth) {
    gl.BindTexture(GL_TEXTURE_2D, texture);
    const GLint filter = smooth ? GL_LINEAR : GL_NEAREST;
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

}  // namespace

void Texture::copy_from_frame(Content content, int x, int gl_y, int width, int height) {
    bind_with_filter(texture_.id(), /*smooth=*/false);
    const bool depth = content == Content::Depth;
    if (width != width_ || height != height_ || !bottom_up_ || depth != holds_depth_) {  // storage of this size and kind
        if (depth)
            gl.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, width, height, 0, GL_DEPTH_COMPONENT,
                          GL_UNSIGNED_INT, nullptr);
        else
            gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE, nullptr);
    }
    gl.CopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, x, gl_y, width, height);
    width_ = width;
    height_ = height;
    bottom_up_ = true;
    holds_depth_ = depth;
}

void Texture::upload_pixels(GLenum format, const void* pixels, int width, int height, bool smooth) {
    bind_with_filter(texture_.id(), smooth);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);  // RGB rows are not padded to 4 bytes
    if (format == GL_RED)
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width, height, 0, GL_RED, GL_FLOAT, pixels);
    else
        gl.TexImage2D(GL_TEXTURE_2D, 0, format == GL_RGB ? GL_RGB8 : GL_RGBA8, width, height, 0, format,
                      GL_UNSIGNED_BYTE, pixels);
    width_ = width;
    height_ = height;
    bottom_up_ = false;
    holds_depth_ = false;
}

}  // namespace accelviz
