#include "app/gl/shader.h"

#include <string>
#include <utility>

namespace accelviz {

namespace {

/// Compiles one stage; on failure returns the file name and the driver's log.
Expected<GLuint> compile_stage(GLenum stage, std::string_view file) {
    const std::string_view text = embedded_shader(file);
    if (text.empty()) return Error{"shader " + std::string(file) + ": not embedded in this binary"};
    const GLuint shader = gl.CreateShader(stage);
    const GLchar* source = text.data();
    const GLint length = GLint(text.size());
    gl.ShaderSource(shader, 1, &source, &length);
    gl.CompileShader(shader);
    GLint ok = GL_FALSE;
    gl.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok) return shader;
    GLint log_length = 0;
    gl.GetShaderiv(shader, GL_INFO_LOG_LENGTH, &log_length);
    std::string log(size_t(log_length > 1 ? log_length : 1), '\0');
    gl.GetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    gl.DeleteShader(shader);
    while (!log.empty() && (log.back() == '\0' || log.back() == '\n')) log.pop_back();
    return Error{"shader " + std::string(file) + ": " + log};
}

}  // namespace

Expected<ShaderProgram> ShaderProgram::from_embedded(std::string_view vertex_file, std::string_view fragment_file) {
    auto vertex = compile_stage(GL_VERTEX_SHADER, vertex_file);
    if (!vertex) return Error{vertex.error()};
    auto fragment = compile_stage(GL_FRAGMENT_SHADER, fragment_file);
    if (!fragment) {
        gl.DeleteShader(*vertex);
        return Error{fragment.error()};
    }
    const GLuint program = gl.CreateProgram();
    gl.AttachShader(program, *vertex);
    gl.AttachShader(program, *fragment);
    gl.LinkProgram(program);
    gl.DeleteShader(*vertex);  // flagged; freed with the program
    gl.DeleteShader(*fragment);
    GLint ok = GL_FALSE;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log(1024, '\0');
        gl.GetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
        gl.DeleteProgram(program);
        log.resize(log.find('\0'));
        return Error{"shader program " + std::string(vertex_file) + " + " + std::string(fragment_file) + ": " + log};
    }
    return ShaderProgram(program);
}

ShaderProgram& ShaderProgram::operator=(ShaderProgram&& other) noexcept {
    if (this != &other) {
        if (id_) gl.DeleteProgram(id_);
        id_ = std::exchange(other.id_, 0);
    }
    return *this;
}

ShaderProgram::~ShaderProgram() {
    if (id_) gl.DeleteProgram(id_);
}

}  // namespace accelviz
