#include "app/gl/imgui_renderer.h"

#include <cstddef>
#include <cstdint>

#include <imgui.h>

namespace accelviz {

Expected<std::unique_ptr<ImGuiRenderer>> ImGuiRenderer::create() {
    std::unique_ptr<ImGuiRenderer> r(new ImGuiRenderer());
    auto program = ShaderProgram::from_embedded("imgui.vert", "imgui.frag");
    if (!program) return Error{program.error()};
    r->program_ = std::move(*program);

    gl.BindVertexArray(r->vertex_array_.id());
    gl.BindBuffer(GL_ARRAY_BUFFER, r->vertices_.id());
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->indices_.id());
    auto attribute = [](GLuint index, GLint size, GLenum type, GLboolean normalised, size_t offset) {
        gl.EnableVertexAttribArray(index);
        gl.VertexAttribPointer(index, size, type, normalised, sizeof(ImDrawVert),
                               reinterpret_cast<const void*>(offset));
    };
    attribute(0, 2, GL_FLOAT, GL_FALSE, offsetof(ImDrawVert, pos));
    attribute(1, 2, GL_FLOAT, GL_FALSE, offsetof(ImDrawVert, uv));
    attribute(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, offsetof(ImDrawVert, col));
    gl.BindVertexArray(0);
    return r;
}

void ImGuiRenderer::upload_fonts() {
    ImGuiIO& io = ImGui::GetIO();
    io.BackendRendererName = "accelviz_gl33";
    io.BackendFlags |= ImGuiBackendFlags_RendererHasVtxOffset;
    unsigned char* pixels = nullptr;
    int width = 0, height = 0;
    io.Fonts->GetTexDataAsRGBA32(&pixels, &width, &height);
    font_atlas_.upload_rgba(pixels, width, height, /*smooth=*/true);
    io.Fonts->SetTexID(reinterpret_cast<ImTextureID>(intptr_t(font_atlas_.id())));
    io.Fonts->ClearTexData();  // the GPU has it now
}

void ImGuiRenderer::render(const ImDrawData* data, int fb_width, int fb_height) {
    if (!data || data->CmdListsCount == 0 || fb_width <= 0 || fb_height <= 0) return;
    const ImVec2 scale = data->FramebufferScale;
    const ImVec2 origin = data->DisplayPos;

    // Blended, no culling or depth, scissored per command.
    gl.Enable(GL_BLEND);
    gl.BlendEquation(GL_FUNC_ADD);
    gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    gl.Disable(GL_CULL_FACE);
    gl.Disable(GL_DEPTH_TEST);
    gl.Enable(GL_SCISSOR_TEST);
    gl.Viewport(0, 0, fb_width, fb_height);

    // Orthographic projection of ImGui's display rectangle (y down) to NDC.
    const float l = origin.x, r = origin.x + data->DisplaySize.x;
    const float t = origin.y, b = origin.y + data->DisplaySize.y;
    const float projection[16] = {2.0f / (r - l), 0, 0, 0,           0, 2.0f / (t - b), 0, 0,
                                  0, 0, -1.0f, 0,                    (r + l) / (l - r), (t + b) / (b - t), 0, 1.0f};
    program_.use();
    gl.UniformMatrix4fv(program_.uniform("projection"), 1, GL_FALSE, projection);
    gl.Uniform1i(program_.uniform("atlas"), 0);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindVertexArray(vertex_array_.id());

    constexpr GLenum index_type = sizeof(ImDrawIdx) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    for (int n = 0; n < data->CmdListsCount; ++n) {
        const ImDrawList* list = data->CmdLists[n];
        gl.BindBuffer(GL_ARRAY_BUFFER, vertices_.id());
        gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(list->VtxBuffer.Size * sizeof(ImDrawVert)), list->VtxBuffer.Data,
                      GL_STREAM_DRAW);
        gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(list->IdxBuffer.Size * sizeof(ImDrawIdx)),
                      list->IdxBuffer.Data, GL_STREAM_DRAW);
        for (const ImDrawCmd& cmd : list->CmdBuffer) {
            if (cmd.UserCallback) {
                // ImDrawCallback_ResetRenderState is the only callback we meet (none of ours).
                if (cmd.UserCallback != ImDrawCallback_ResetRenderState) cmd.UserCallback(list, &cmd);
                continue;
            }
            // Clip rectangle in framebuffer pixels; GL's scissor rows are bottom-up.
            const float x0 = (cmd.ClipRect.x - origin.x) * scale.x, y0 = (cmd.ClipRect.y - origin.y) * scale.y;
            const float x1 = (cmd.ClipRect.z - origin.x) * scale.x, y1 = (cmd.ClipRect.w - origin.y) * scale.y;
            if (x1 <= x0 || y1 <= y0) continue;
            gl.Scissor(GLint(x0), GLint(fb_height - y1), GLsizei(x1 - x0), GLsizei(y1 - y0));
            gl.BindTexture(GL_TEXTURE_2D, GLuint(reinterpret_cast<intptr_t>(cmd.GetTexID())));
            gl.DrawElementsBaseVertex(GL_TRIANGLES, GLsizei(cmd.ElemCount), index_type,
                                      reinterpret_cast<const void*>(size_t(cmd.IdxOffset) * sizeof(ImDrawIdx)),
                                      GLint(cmd.VtxOffset));
        }
    }
    gl.BindVertexArray(0);
    gl.Disable(GL_SCISSOR_TEST);
}

}  // namespace accelviz
