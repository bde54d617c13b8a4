#include "app/gl/renderer.h"

#include <algorithm>
#include <cstddef>

#include "app/gl/imgui_renderer.h"

namespace accelviz {

namespace {

static_assert(sizeof(Vec3) == 12, "Mesh positions are uploaded as tightly packed vec3");
static_assert(sizeof(BoxInstance) == 28);
static_assert(sizeof(ColouredVertex) == 16);

/// Depth bias of edges and quads, in NDC z (see Renderer::draw_boxes).
constexpr float kEdgeDepthBias = 2e-5f;

/// GL's bottom-up row of a top-down rectangle.
GLint gl_row(const ViewRect& rect, int frame_height) { return frame_height - rect.y - rect.height; }

/// A float attribute fed from the bound GL_ARRAY_BUFFER.
void float_attribute(GLuint index, GLint size, GLenum type, GLboolean normalised, size_t stride, size_t offset,
                     GLuint divisor = 0) {
    gl.EnableVertexAttribArray(index);
    gl.VertexAttribPointer(index, size, type, normalised, GLsizei(stride), reinterpret_cast<const void*>(offset));
    if (divisor) gl.VertexAttribDivisor(index, divisor);
}

/// Translucent drawing over the depth-tested scene: depth test (less or equal, so
/// an edge drawn on a face shows), no depth writes (what lies behind stays
/// visible and the depth buffer keeps the mesh alone), and "over" blending.
void set_translucent_state() {
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_LEQUAL);
    gl.DepthMask(GL_FALSE);
    gl.Enable(GL_BLEND);
    gl.BlendEquation(GL_FUNC_ADD);
    gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
}

}  // namespace

// [SECTION] GPU buffers

MeshBuffer::MeshBuffer() {
    gl.BindVertexArray(vertex_array_.id());
    gl.BindBuffer(GL_ARRAY_BUFFER, positions_.id());
    float_attribute(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vec3), 0);
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, indices_.id());  // recorded in the vertex array
    gl.BindVertexArray(0);
}

void MeshBuffer::upload(const Mesh& mesh) {
    gl.BindVertexArray(vertex_array_.id());
    gl.BindBuffer(GL_ARRAY_BUFFER, positions_.id());
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(mesh.positions.size() * sizeof(Vec3)), mesh.positions.data(),
                  GL_STATIC_DRAW);
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(mesh.indices.size() * sizeof(mesh.indices[0])),
                  mesh.indices.data(), GL_STATIC_DRAW);
    gl.BindVertexArray(0);
    triangle_count_ = mesh.indices.size();
}

BoxBuffer::BoxBuffer() {
    gl.BindVertexArray(vertex_array_.id());
    point_instances_at(0);
    // Corner c has bit 0: x, bit 1: y, bit 2: z at the box's hi side.
    static constexpr uint8_t kEdges[24] = {0, 1, 2, 3, 4, 5, 6, 7,   // edges along x
                                           0, 2, 1, 3, 4, 6, 5, 7,   // along y
                                           0, 4, 1, 5, 2, 6, 3, 7};  // along z
    gl.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, edge_indices_.id());  // recorded in the vertex array
    gl.BufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof kEdges, kEdges, GL_STATIC_DRAW);
    gl.BindVertexArray(0);
}

void BoxBuffer::point_instances_at(size_t first) const {
    const size_t base = first * sizeof(BoxInstance);
    gl.BindBuffer(GL_ARRAY_BUFFER, instances_.id());
    float_attribute(0, 3, GL_FLOAT, GL_FALSE, sizeof(BoxInstance), base + offsetof(BoxInstance, lo), 1);
    float_attribute(1, 3, GL_FLOAT, GL_FALSE, sizeof(BoxInstance), base + offsetof(BoxInstance, hi), 1);
    float_attribute(2, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(BoxInstance), base + offsetof(BoxInstance, colour), 1);
}

void BoxBuffer::upload(const std::vector<BoxInstance>& boxes) {
    gl.BindBuffer(GL_ARRAY_BUFFER, instances_.id());
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(boxes.size() * sizeof(BoxInstance)), boxes.data(), GL_STATIC_DRAW);
    count_ = boxes.size();
    translucent_ = std::any_of(boxes.begin(), boxes.end(), [](const BoxInstance& b) { return b.colour.a < 255; });
}

ColouredBuffer::ColouredBuffer() {
    gl.BindVertexArray(vertex_array_.id());
    gl.BindBuffer(GL_ARRAY_BUFFER, vertices_.id());
    float_attribute(0, 3, GL_FLOAT, GL_FALSE, sizeof(ColouredVertex), offsetof(ColouredVertex, position));
    float_attribute(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, sizeof(ColouredVertex), offsetof(ColouredVertex, colour));
    gl.BindVertexArray(0);
}

void ColouredBuffer::upload(const std::vector<ColouredVertex>& vertices) {
    gl.BindBuffer(GL_ARRAY_BUFFER, vertices_.id());
    gl.BufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(ColouredVertex)), vertices.data(),
                  GL_STATIC_DRAW);
    count_ = vertices.size();
}

void ColouredBuffer::upload_segments(const std::vector<ColouredVertex>& ends) { upload(ends); }

void ColouredBuffer::upload_quads(const std::vector<ColouredQuad>& quads) {
    std::vector<ColouredVertex> triangles;
    triangles.reserve(quads.size() * 6);
    for (const ColouredQuad& q : quads)
        for (int corner : {0, 1, 2, 0, 2, 3}) triangles.push_back({q.corners[corner], q.colour});
    upload(triangles);
}

// [SECTION] Renderer

Expected<std::unique_ptr<Renderer>> Renderer::create() {
    std::unique_ptr<Renderer> r(new Renderer());
    struct Program { ShaderProgram* out; const char* vertex; const char* fragment; const char* geometry; };
    for (const Program& p : {Program{&r->mesh_program_, "mesh.vert", "mesh.frag", ""},
                             Program{&r->boxes_program_, "boxes.vert", "coloured.frag", ""},
                             Program{&r->coloured_program_, "coloured.vert", "coloured.frag", ""},
                             Program{&r->thick_boxes_program_, "boxes.vert", "thick_lines.frag", "thick_lines.geom"},
                             Program{&r->thick_coloured_program_, "coloured.vert", "thick_lines.frag",
                                     "thick_lines.geom"},
                             Program{&r->image_program_, "image.vert", "image.frag", ""},
                             Program{&r->image_depth_program_, "image.vert", "image_depth.frag", ""}}) {
        auto program = ShaderProgram::from_embedded(p.vertex, p.fragment, p.geometry);
        if (!program) return Error{program.error()};
        *p.out = std::move(*program);
    }
    auto imgui = ImGuiRenderer::create();
    if (!imgui) return Error{imgui.error()};
    r->imgui_ = std::move(*imgui);
    // A multisampled frame (antialiasing a driver may force) cannot be copied into a
    // texture (glCopyTexSubImage2D: GL_INVALID_OPERATION).
    GLint sample_buffers = 0;
    gl.GetIntegerv(GL_SAMPLE_BUFFERS, &sample_buffers);
    r->frame_copies_work_ = sample_buffers == 0;
    return r;
}

Renderer::~Renderer() = default;

void Renderer::begin_frame(int fb_width, int fb_height, Rgb background) {
    frame_width_ = fb_width;
    frame_height_ = fb_height;
    gl.Disable(GL_SCISSOR_TEST);
    gl.Viewport(0, 0, fb_width, fb_height);
    gl.ClearColor(background.r / 255.0f, background.g / 255.0f, background.b / 255.0f, 1.0f);
    gl.ClearDepth(1.0);
    gl.DepthMask(GL_TRUE);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
}

void Renderer::set_gl_viewport(const ViewRect& rect) {
    const GLint row = gl_row(rect, frame_height_);
    gl.Viewport(rect.x, row, rect.width, rect.height);
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(rect.x, row, rect.width, rect.height);
}

void Renderer::begin_view(const View3D& view) {
    view_ = view;
    set_gl_viewport(view.rect);
    gl.DepthMask(GL_TRUE);
    gl.Clear(GL_DEPTH_BUFFER_BIT);
}

void Renderer::use_view_program(const ShaderProgram& program) {
    program.use();
    gl.UniformMatrix4fv(program.uniform("view_projection"), 1, GL_FALSE, view_.view_projection.data());
}

void Renderer::draw_mesh(const MeshBuffer& mesh, const MeshStyle& style) {
    if (mesh.triangle_count() == 0) return;
    use_view_program(mesh_program_);
    const Vec3 eye = to_float(view_.camera.eye);
    gl.Uniform3f(mesh_program_.uniform("eye"), eye.x, eye.y, eye.z);
    gl.Uniform3f(mesh_program_.uniform("base_colour"), style.base_colour.r / 255.0f, style.base_colour.g / 255.0f,
                 style.base_colour.b / 255.0f);
    gl.Uniform1f(mesh_program_.uniform("opacity"), style.opacity);
    gl.Enable(GL_DEPTH_TEST);
    gl.BindVertexArray(mesh.vertex_array_.id());
    const GLsizei count = GLsizei(mesh.triangle_count() * 3);
    if (style.opacity >= 1.0f) {
        gl.Disable(GL_BLEND);
        gl.DepthFunc(GL_LESS);
        gl.DepthMask(GL_TRUE);
        gl.DrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
    } else {
        // Translucent: depth first (colour off), then colour where the depth is
        // the nearest surface's, blended. So only the nearest surface tints what
        // lies behind it, however the triangles are ordered.
        gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        gl.DepthFunc(GL_LESS);
        gl.DepthMask(GL_TRUE);
        gl.DrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
        gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        gl.DepthFunc(GL_LEQUAL);
        gl.DepthMask(GL_FALSE);
        gl.Enable(GL_BLEND);
        gl.BlendEquation(GL_FUNC_ADD);
        gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
        gl.DrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, nullptr);
    }
    gl.BindVertexArray(0);
    gl.DepthMask(GL_TRUE);
}

const ShaderProgram& Renderer::line_program(bool boxes) const {
    const bool thick = line_width_ > 1.01f;
    if (boxes) return thick ? thick_boxes_program_ : boxes_program_;
    return thick ? thick_coloured_program_ : coloured_program_;
}

void Renderer::use_line_program(bool boxes) {
    const ShaderProgram& program = line_program(boxes);
    use_view_program(program);
    gl.Uniform1f(program.uniform("depth_bias"), kEdgeDepthBias);
    gl.Uniform2f(program.uniform("viewport_size"), float(view_.rect.width), float(view_.rect.height));
    gl.Uniform1f(program.uniform("line_width"), line_width_);
}

void Renderer::draw_boxes(const BoxBuffer& boxes, size_t count, size_t first) {
    if (first >= boxes.size()) return;
    count = std::min(count, boxes.size() - first);
    if (count == 0) return;
    use_line_program(/*boxes=*/true);
    // The depth buffer keeps the mesh alone (read back as the raster depth).
    set_translucent_state();
    if (!boxes.translucent_) gl.Disable(GL_BLEND);  // opaque boxes: measurably faster on llvmpipe
    gl.BindVertexArray(boxes.vertex_array_.id());
    // From box `first` on: the instance attributes point that far into the buffer (GL
    // 3.3 has no base instance), and back to its start after.
    if (first > 0) boxes.point_instances_at(first);
    // 12 edges per box, every box at once.
    gl.DrawElementsInstanced(GL_LINES, 24, GL_UNSIGNED_BYTE, nullptr, GLsizei(count));
    if (first > 0) boxes.point_instances_at(0);
    gl.BindVertexArray(0);
    gl.DepthMask(GL_TRUE);
}

void Renderer::draw_segments(const ColouredBuffer& segments) {
    if (segments.vertex_count() < 2) return;
    use_line_program(/*boxes=*/false);
    set_translucent_state();
    gl.BindVertexArray(segments.vertex_array_.id());
    gl.DrawArrays(GL_LINES, 0, GLsizei(segments.vertex_count()));
    gl.BindVertexArray(0);
    gl.DepthMask(GL_TRUE);
}

void Renderer::draw_quads(const ColouredBuffer& quads, size_t count) {
    const size_t vertices = std::min(quads.vertex_count(), count == SIZE_MAX ? count : 6 * count);  // two triangles a quad
    if (vertices < 3) return;
    use_view_program(coloured_program_);
    gl.Uniform1f(coloured_program_.uniform("depth_bias"), kEdgeDepthBias);
    set_translucent_state();
    gl.BindVertexArray(quads.vertex_array_.id());
    gl.DrawArrays(GL_TRIANGLES, 0, GLsizei(vertices));
    gl.BindVertexArray(0);
    gl.DepthMask(GL_TRUE);
}

void Renderer::draw_image(const Texture& texture, const ViewRect& rect) {
    if (texture.empty() || rect.empty()) return;
    gl.Disable(GL_SCISSOR_TEST);
    gl.Viewport(0, 0, frame_width_, frame_height_);
    gl.Disable(GL_DEPTH_TEST);
    gl.Disable(GL_BLEND);
    image_program_.use();
    // Rectangle in NDC: x right, y up.
    const float left = 2.0f * rect.x / frame_width_ - 1.0f;
    const float right = 2.0f * (rect.x + rect.width) / frame_width_ - 1.0f;
    float top = 1.0f - 2.0f * rect.y / frame_height_;
    float bottom = 1.0f - 2.0f * (rect.y + rect.height) / frame_height_;
    if (texture.bottom_up()) std::swap(top, bottom);  // its first row at the bottom
    gl.Uniform4f(image_program_.uniform("rect"), left, top, right, bottom);
    gl.Uniform1i(image_program_.uniform("image"), 0);
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, texture.id());
    gl.BindVertexArray(empty_vertex_array_.id());
    gl.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    gl.BindVertexArray(0);
}

void Renderer::draw_image_with_depth(const Texture& colour, const Texture& depth, float opacity, bool far_pixels) {
    if (colour.empty() || depth.empty() || view_.rect.empty()) return;
    set_gl_viewport(view_.rect);
    image_depth_program_.use();
    // The whole view; a texture copied from the frame has its first row at the bottom.
    const float top = colour.bottom_up() ? -1.0f : 1.0f;
    gl.Uniform4f(image_depth_program_.uniform("rect"), -1.0f, top, 1.0f, -top);
    gl.Uniform1i(image_depth_program_.uniform("image"), 0);
    gl.Uniform1i(image_depth_program_.uniform("depth"), 1);
    gl.Uniform1f(image_depth_program_.uniform("opacity"), opacity);
    gl.Uniform1i(image_depth_program_.uniform("far_pixels"), far_pixels ? 1 : 0);
    gl.Enable(GL_DEPTH_TEST);
    gl.DepthFunc(GL_ALWAYS);  // the picture is the nearest surface already
    gl.DepthMask(GL_TRUE);
    if (opacity >= 1.0f) {
        gl.Disable(GL_BLEND);
    } else {
        gl.Enable(GL_BLEND);
        gl.BlendEquation(GL_FUNC_ADD);
        gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
    }
    gl.ActiveTexture(GL_TEXTURE1);
    gl.BindTexture(GL_TEXTURE_2D, depth.id());
    gl.ActiveTexture(GL_TEXTURE0);
    gl.BindTexture(GL_TEXTURE_2D, colour.id());
    gl.BindVertexArray(empty_vertex_array_.id());
    gl.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);
    gl.BindVertexArray(0);
    gl.DepthFunc(GL_LESS);
    gl.Disable(GL_BLEND);
}

void Renderer::finish() { gl.Finish(); }

void Renderer::draw_imgui(const ImDrawData* data) { imgui_->render(data, frame_width_, frame_height_); }

Image Renderer::read_colour(const ViewRect& rect) const {
    std::vector<uint8_t> rgb(size_t(rect.width) * rect.height * 3);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 1);  // tight RGB rows
    gl.ReadPixels(rect.x, gl_row(rect, frame_height_), rect.width, rect.height, GL_RGB, GL_UNSIGNED_BYTE,
                  rgb.data());
    Image image(rect.width, rect.height);
    for (int y = 0; y < rect.height; ++y) {  // GL rows are bottom-up
        const uint8_t* row = rgb.data() + size_t(rect.height - 1 - y) * rect.width * 3;
        for (int x = 0; x < rect.width; ++x) image.at(x, y) = {row[3 * x], row[3 * x + 1], row[3 * x + 2]};
    }
    return image;
}

void Renderer::copy_to_texture(const ViewRect& rect, Texture::Content content, Texture& texture) const {
    texture.copy_from_frame(content, rect.x, gl_row(rect, frame_height_), rect.width, rect.height);
}

void Renderer::prepare_frame_copies() const {
    if (!frame_copies_work_) return;
    Texture colour, depth;
    colour.copy_from_frame(Texture::Content::Colour, 0, 0, 1, 1);
    depth.copy_from_frame(Texture::Content::Depth, 0, 0, 1, 1);
    gl.Finish();
}

std::vector<float> Renderer::read_depth(const ViewRect& rect) const {
    std::vector<float> bottom_up(size_t(rect.width) * rect.height);
    gl.PixelStorei(GL_PACK_ALIGNMENT, 4);
    gl.ReadPixels(rect.x, gl_row(rect, frame_height_), rect.width, rect.height, GL_DEPTH_COMPONENT, GL_FLOAT,
                  bottom_up.data());
    std::vector<float> depth(bottom_up.size());
    for (int y = 0; y < rect.height; ++y)
        std::copy_n(bottom_up.begin() + ptrdiff_t(rect.height - 1 - y) * rect.width, rect.width,
                    depth.begin() + ptrdiff_t(y) * rect.width);
    return depth;
}

}  // namespace accelviz
