#pragma once
/// Where GL draws: a GLFW window or an OSMesa buffer. The renderer and
/// draw_frame() see only this, so the window and headless renders run the same
/// code; only the context differs.

namespace accelviz {

class GlContext {
public:
    virtual ~GlContext() = default;
    /// Makes the context current on this thread and (re)loads the `gl` table.
    /// Returns false if a required GL function is missing.
    virtual bool make_current() = 0;
    /// Size of the default framebuffer in pixels.
    virtual int framebuffer_width() const = 0;
    virtual int framebuffer_height() const = 0;
};

}  // namespace accelviz
