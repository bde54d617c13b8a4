#include "app/gl/shader.h"

#include <string>
#include <utility>
#include <vector>

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

struct Stage {
    GLenum type;
    std::string_view file;
};

/// Compiles the stages (those with a file) and links them.
Expected<GLuint> link_program(std::initializer_list<Stage> stages, const std::string& name) {
    std::vector<GLuint> shaders;
    for (const Stage& stage : stages) {
        if (stage.file.empty()) continue;
        auto shader = compile_stage(stage.type, stage.file);
        if (!shader) {
            for (GLuint s : shaders) gl.DeleteShader(s);
            return Error{shader.error()};
        }
        shaders.push_back(*shader);
    }
    const GLuint program = gl.CreateProgram();
    for (GLuint s : shaders) gl.AttachShader(program, s);
    gl.LinkProgram(program);
    for (GLuint s : shaders) gl.DeleteShader(s);  // flagged; freed with the program
    GLint ok = GL_FALSE;
    gl.GetProgramiv(program, GL_LINK_STATUS, &ok);
    if (!ok) {
        std::string log(1024, '\0');
        gl.GetProgramInfoLog(program, GLsizei(log.size()), nullptr, log.data());
        gl.DeleteProgram(program);
        log.resize(log.find('\0'));
        return Error{"shader program " + name + ": " + log};
    }
    return program;
}

}  // namespace

Expected<ShaderProgram> ShaderProgram::from_embedded(std::string_view vertex_file, std::string_view fragment_file,
                                                     std::string_view geometry_file) {
    auto program = link_program({Stage{GL_VERTEX_SHADER, vertex_file}, Stage{GL_GEOMETRY_SHADER, geometry_file},
                                 Stage{GL_FRAGMENT_SHADER, fragment_file}},
                                std::string(vertex_file) + " + " + std::string(fragment_file));
    if (!program) return Error{program.error()};
    return ShaderProgram(*program);
}

Expected<ShaderProgram> ShaderProgram::compute_from_embedded(std::string_view compute_file) {
    if (!gl.has_compute) return Error{"compute shaders need OpenGL 4.3; this context is " + gl_description()};
    auto program = link_program({Stage{GL_COMPUTE_SHADER, compute_file}}, std::string(compute_file));
    if (!program) return Error{program.error()};
    return ShaderProgram(*program);
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
