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

void Texture::upload_pixels(GLenum format, const void* pixels, int width, int height, bool smooth) {
    gl.BindTexture(GL_TEXTURE_2D, texture_.id());
    const GLint filter = smooth ? GL_LINEAR : GL_NEAREST;
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, filter);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, filter);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl.PixelStorei(GL_UNPACK_ALIGNMENT, 1);  // RGB rows are not padded to 4 bytes
    if (format == GL_RED)
        gl.TexImage2D(GL_TEXTURE_2D, 0, GL_R32F, width, height, 0, GL_RED, GL_FLOAT, pixels);
    else
        gl.TexImage2D(GL_TEXTURE_2D, 0, format == GL_RGB ? GL_RGB8 : GL_RGBA8, width, height, 0, format,
                      GL_UNSIGNED_BYTE, pixels);
    width_ = width;
    height_ = height;
}

}  // namespace accelviz
