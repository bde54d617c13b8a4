#pragma once
/// A headless OpenGL 3.3 core context (Mesa's llvmpipe, which reports 4.5 core)
/// drawing into a buffer in memory. <GL/osmesa.h> is included only by the .cpp:
/// it pulls in <GL/gl.h>, which must stay away from gl_loader.h.

#include <memory>
#include <string>
#include <vector>

#include "app/platform/gl_context.h"
#include "core/util/expected.h"

namespace accelviz {

class OsMesaContext final : public GlContext {
public:
    /// Creates a core-profile context with an RGBA colour buffer and a 24-bit
    /// depth buffer of width x height, makes it current and loads `gl`.
    static Expected<std::unique_ptr<OsMesaContext>> create(int width, int height);
    ~OsMesaContext() override;
    OsMesaContext(const OsMesaContext&) = delete;
    OsMesaContext& operator=(const OsMesaContext&) = delete;

    bool make_current() override;
    int framebuffer_width() const override { return width_; }
    int framebuffer_height() const override { return height_; }
    /// "4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)".
    std::string description() const;

private:
    OsMesaContext() = default;
    void* context_ = nullptr;  ///< OSMesaContext (an opaque pointer)
    std::vector<unsigned char> buffer_;  ///< RGBA8, what OSMesa draws into
    int width_ = 0, height_ = 0;
};

}  // namespace accelviz
