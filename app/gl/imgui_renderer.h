#pragma once
/// Our own renderer for Dear ImGui's draw lists, on the same GL loader as the rest
/// (ImGui 1.86's OpenGL3 backend would bring its own loader, which cannot see an
/// OSMesa context: see docs/PLATFORM.md). About what imgui_impl_opengl3 does, for
/// GL 3.3 core only: one textured, vertex-coloured, scissored triangle list per
/// draw command, with the font atlas as a texture.

#include <memory>

#include "app/gl/gl_objects.h"
#include "app/gl/shader.h"
#include "app/gl/texture.h"

struct ImDrawData;

namespace accelviz {

class ImGuiRenderer {
public:
    static Expected<std::unique_ptr<ImGuiRenderer>> create();

    /// Builds the current ImGui context's font atlas (if needed) and uploads it
    /// as a texture. Call after changing fonts, before ImGui::NewFrame().
    void upload_fonts();
    /// Draws the lists over the whole framebuffer (fb_width x fb_height pixels).
    /// Sets io.BackendFlags' RendererHasVtxOffset: large lists need it.
    void render(const ImDrawData* data, int fb_width, int fb_height);

private:
    ImGuiRenderer() = default;
    ShaderProgram program_;
    GlVertexArray vertex_array_;
    GlBuffer vertices_, indices_;
    Texture font_atlas_;
};

}  // namespace accelviz
