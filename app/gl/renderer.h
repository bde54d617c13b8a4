#pragma once
/// The GL 3.3 core renderer shared by the window and headless rendering: the
/// scene mesh with headlight shading, wireframe boxes (instanced: one draw call
/// for any number), line segments, translucent quads, textured image rectangles,
/// and Dear ImGui's draw lists. It knows nothing about panels or AppState;
/// draw_frame() (app/gui) decides what to draw.
///
/// GPU data lives in the *Buffer classes below, owned by whoever produces it
/// (upload once, draw every frame). All calls need the context current.

#include <cstdint>
#include <memory>
#include <vector>

#include "app/gl/gl_objects.h"
#include "app/gl/shader.h"
#include "app/gl/texture.h"
#include "app/gl/view3d.h"
#include "core/geometry/mesh.h"
#include "core/render/image.h"

struct ImDrawData;

namespace accelviz {

/// 8-bit colour with opacity (a = 255: opaque).
struct Rgba8 {
    uint8_t r = 0, g = 0, b = 0, a = 255;
};

/// One wireframe box: its corners and colour.
struct BoxInstance {
    Vec3 lo, hi;
    Rgba8 colour;
};

/// A vertex of a line segment or translucent quad.
struct ColouredVertex {
    Vec3 position;
    Rgba8 colour;
};

/// A flat quad with corners in order around its edge.
struct ColouredQuad {
    Vec3 corners[4];
    Rgba8 colour;
};

/// The scene mesh on the GPU: positions and triangle indices as in Mesh.
class MeshBuffer {
public:
    MeshBuffer();
    void upload(const Mesh& mesh);
    size_t triangle_count() const { return triangle_count_; }

private:
    friend class Renderer;
    GlVertexArray vertex_array_;
    GlBuffer positions_, indices_;
    size_t triangle_count_ = 0;
};

/// Wireframe boxes on the GPU, one instance each.
class BoxBuffer {
public:
    BoxBuffer();
    void upload(const std::vector<BoxInstance>& boxes);
    size_t size() const { return count_; }

private:
    friend class Renderer;
    /// The vertex array's instance attributes read from box `first` on (its array bound).
    void point_instances_at(size_t first) const;
    GlVertexArray vertex_array_;
    GlBuffer instances_;
    GlBuffer edge_indices_;  ///< the 24 corner indices of the 12 edges, shared by every instance
    size_t count_ = 0;
    bool translucent_ = false;  ///< some colour has alpha < 255: blend
};

/// Line segments (GL_LINES: vertices 2i and 2i+1 form segment i) or triangles
/// (translucent quads, split in two), position + colour per vertex.
class ColouredBuffer {
public:
    ColouredBuffer();
    /// Segments: an even number of vertices.
    void upload_segments(const std::vector<ColouredVertex>& ends);
    /// Quads, each drawn as two triangles.
    void upload_quads(const std::vector<ColouredQuad>& quads);
    size_t vertex_count() const { return count_; }

private:
    friend class Renderer;
    void upload(const std::vector<ColouredVertex>& vertices);
    GlVertexArray vertex_array_;
    GlBuffer vertices_;
    size_t count_ = 0;
};

/// How to draw the mesh.
struct MeshStyle {
    Rgb base_colour{225, 205, 170};  ///< what the CPU renderers use (core/render/shading.h)
    /// < 1: the nearest surface is blended over what was drawn before it (it
    /// still writes depth, so what is drawn after it and behind it stays hidden).
    float opacity = 1.0f;
};

class ImGuiRenderer;

class Renderer {
public:
    /// Compiles the shaders (the context must be current). Errors carry the
    /// shader file and the driver's log.
    static Expected<std::unique_ptr<Renderer>> create();
    ~Renderer();

    /// Starts a frame of fb_width x fb_height pixels, cleared to `background`.
    void begin_frame(int fb_width, int fb_height, Rgb background);

    /// Width in pixels of box edges and segments (1: plain GL lines; more: each
    /// line widened into a quad by a geometry shader, for projectors).
    void set_line_width(float pixels) { line_width_ = pixels; }

    /// Restricts drawing to view.rect, clears its depth, and uses its camera for
    /// the 3D draws below.
    void begin_view(const View3D& view);
    void draw_mesh(const MeshBuffer& mesh, const MeshStyle& style);
    /// Boxes, segments and quads are depth-tested but write no depth: the depth
    /// buffer holds the mesh alone (the window's raster depth, read back and
    /// compared with the ray caster). They are drawn slightly towards the eye (a
    /// constant NDC depth bias), so edges lying on a surface are not hidden by it.
    /// `count`: `count` boxes from box `first` on (SIZE_MAX: to the last), in order.
    void draw_boxes(const BoxBuffer& boxes, size_t count = SIZE_MAX, size_t first = 0);
    void draw_segments(const ColouredBuffer& segments);
    /// Translucent: blended, tested against depth but not writing it. `count`: the
    /// first `count` quads only (SIZE_MAX: all).
    void draw_quads(const ColouredBuffer& quads, size_t count = SIZE_MAX);

    /// The mesh as a ray-cast picture instead of triangles: `colour` stretched over
    /// the current view's rectangle, `depth` (depth-buffer values, 1 = no hit: left
    /// to the background) written to the z-buffer, so the boxes, segments and quads
    /// drawn after it are hidden behind the surface as behind draw_mesh's.
    /// `opacity` < 1 blends it like a translucent mesh. `far_pixels`: the pixels at
    /// depth 1 are drawn too (a picture of the view copied with its depth).
    void draw_image_with_depth(const Texture& colour, const Texture& depth, float opacity = 1.0f,
                               bool far_pixels = false);
    /// A texture stretched over a rectangle of the frame (screen space).
    void draw_image(const Texture& texture, const ViewRect& rect);
    /// Waits until the GPU (or llvmpipe) has drawn everything asked so far (timing).
    void finish();
    /// Dear ImGui's draw lists for this frame (over everything else).
    void draw_imgui(const ImDrawData* data);
    ImGuiRenderer& imgui() { return *imgui_; }

    /// Reads back colour (top row first) or depth in [0, 1] (top row first) of a
    /// rectangle of the current frame.
    Image read_colour(const ViewRect& rect) const;
    std::vector<float> read_depth(const ViewRect& rect) const;
    /// Copies the colour or the depth of a rectangle of the current frame into a
    /// texture, which draw_image and draw_image_with_depth then show the right way up
    /// (both textures of the latter copied, or both uploaded). Only where
    /// frame_copies_work(): not from a multisampled frame.
    void copy_to_texture(const ViewRect& rect, Texture::Content content, Texture& texture) const;
    bool frame_copies_work() const { return frame_copies_work_; }
    /// A software renderer (llvmpipe) compiles its copy of a frame's colour and depth
    /// into a texture the first time it makes one, tens of milliseconds: a window does
    /// that once at its start, so that no frame pays it (a still view kept as a
    /// picture copies itself every frame it is drawn in shares: ViewCache).
    void prepare_frame_copies() const;

private:
    Renderer() = default;
    bool frame_copies_work_ = true;  ///< the frame is not multisampled (create())
    void set_gl_viewport(const ViewRect& rect);
    void use_view_program(const ShaderProgram& program);

    /// The program for lines (boxes or segments) at the current width.
    const ShaderProgram& line_program(bool boxes) const;
    void use_line_program(bool boxes);

    ShaderProgram mesh_program_, boxes_program_, coloured_program_, image_program_, image_depth_program_;
    ShaderProgram thick_boxes_program_, thick_coloured_program_;  ///< with thick_lines.geom
    float line_width_ = 1.0f;
    GlVertexArray empty_vertex_array_;  ///< for draws that compute vertices from gl_VertexID
    std::unique_ptr<ImGuiRenderer> imgui_;
    View3D view_;
    int frame_width_ = 0, frame_height_ = 0;
};

}  // namespace accelviz
