// The only file that includes <GL/osmesa.h> (and with it <GL/gl.h>).
#include "app/platform/osmesa_context.h"

#include <GL/osmesa.h>

#include "app/platform/gl_lookup.h"

namespace accelviz {

namespace {

void* osmesa_lookup(const char* name) { return reinterpret_cast<void*>(OSMesaGetProcAddress(name)); }

}  // namespace

Expected<std::unique_ptr<OsMesaContext>> OsMesaContext::create(int width, int height) {
    if (width <= 0 || height <= 0 || width > 16384 || height > 16384)
        return Error{"headless GL: image size must be between 1 and 16384 pixels"};
    const int attributes[] = {OSMESA_FORMAT, OSMESA_RGBA,
                              OSMESA_DEPTH_BITS, 24,
                              OSMESA_STENCIL_BITS, 8,
                              OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                              OSMESA_CONTEXT_MAJOR_VERSION, 3,
                              OSMESA_CONTEXT_MINOR_VERSION, 3,
                              0};
    std::unique_ptr<OsMesaContext> ctx(new OsMesaContext());
    ctx->context_ = OSMesaCreateContextAttribs(attributes, nullptr);
    if (!ctx->context_)
        return Error{"headless GL: OSMesa could not create an OpenGL 3.3 core context "
                     "(is libgl1-mesa-dri installed?)"};
    ctx->width_ = width;
    ctx->height_ = height;
    ctx->buffer_.resize(size_t(width) * height * 4);
    if (!ctx->make_current()) return Error{"headless GL: OSMesa context lacks required OpenGL functions"};
    return ctx;
}

OsMesaContext::~OsMesaContext() {
    if (context_) OSMesaDestroyContext(static_cast<OSMesaContext>(context_));
}

bool OsMesaContext::make_current() {
    if (!OSMesaMakeCurrent(static_cast<OSMesaContext>(context_), buffer_.data(), GL_UNSIGNED_BYTE, width_,
                           height_))
        return false;
    return load_gl(&osmesa_lookup, nullptr);
}

std::string OsMesaContext::description() const { return gl_description(); }

}  // namespace accelviz
