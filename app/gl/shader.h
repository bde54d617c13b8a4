#pragma once
/// GLSL programs built from the shaders embedded in the binary (shaders/*.vert,
/// *.frag, embedded at build time by shaders/embed_shaders.cmake).

#include <string>
#include <string_view>

#include "app/platform/gl_loader.h"
#include "core/util/expected.h"

namespace accelviz {

/// The text of an embedded shader file ("mesh.vert"); empty if there is none.
std::string_view embedded_shader(std::string_view name);

/// A linked vertex + fragment program. Move-only; deletes the program when destroyed.
class ShaderProgram {
public:
    /// Compiles and links two embedded files. The error names the file and
    /// carries the driver's log.
    /// With `geometry_file` non-empty, a geometry stage goes between them.
    static Expected<ShaderProgram> from_embedded(std::string_view vertex_file, std::string_view fragment_file,
                                                 std::string_view geometry_file = {});
    /// Compiles and links one embedded compute shader (OpenGL 4.3: gl.has_compute).
    static Expected<ShaderProgram> compute_from_embedded(std::string_view compute_file);

    ShaderProgram() = default;
    ShaderProgram(ShaderProgram&& other) noexcept : id_(other.id_) { other.id_ = 0; }
    ShaderProgram& operator=(ShaderProgram&& other) noexcept;
    ShaderProgram(const ShaderProgram&) = delete;
    ShaderProgram& operator=(const ShaderProgram&) = delete;
    ~ShaderProgram();

    void use() const { gl.UseProgram(id_); }
    /// Location of a uniform (-1 if the linker removed it: setting it is then a no-op).
    GLint uniform(const char* name) const { return gl.GetUniformLocation(id_, name); }
    GLuint id() const { return id_; }

private:
    explicit ShaderProgram(GLuint id) : id_(id) {}
    GLuint id_ = 0;
};

}  // namespace accelviz
