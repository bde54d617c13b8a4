#pragma once
/// Owning handles for GL objects: each creates its object when constructed
/// (a context must be current) and deletes it when destroyed. Move-only.

#include <utility>

#include "app/platform/gl_loader.h"

namespace accelviz {

/// One GL object name, created by Create and deleted by Delete.
template <void (*Create)(GLuint*), void (*Delete)(GLuint)>
class GlObject {
public:
    GlObject() { Create(&id_); }
    ~GlObject() {
        if (id_) Delete(id_);
    }
    GlObject(GlObject&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
    GlObject& operator=(GlObject&& other) noexcept {
        if (this != &other) {
            if (id_) Delete(id_);
            id_ = std::exchange(other.id_, 0);
        }
        return *this;
    }
    GlObject(const GlObject&) = delete;
    GlObject& operator=(const GlObject&) = delete;

    GLuint id() const { return id_; }

private:
    GLuint id_ = 0;
};

namespace gl_object_detail {
inline void create_buffer(GLuint* id) { gl.GenBuffers(1, id); }
inline void delete_buffer(GLuint id) { gl.DeleteBuffers(1, &id); }
inline void create_vertex_array(GLuint* id) { gl.GenVertexArrays(1, id); }
inline void delete_vertex_array(GLuint id) { gl.DeleteVertexArrays(1, &id); }
inline void create_texture(GLuint* id) { gl.GenTextures(1, id); }
inline void delete_texture(GLuint id) { gl.DeleteTextures(1, &id); }
}  // namespace gl_object_detail

/// A buffer object (vertex, instance or index data).
using GlBuffer = GlObject<gl_object_detail::create_buffer, gl_object_detail::delete_buffer>;
/// A vertex array object: which buffers feed which vertex attributes.
using GlVertexArray = GlObject<gl_object_detail::create_vertex_array, gl_object_detail::delete_vertex_array>;
/// A texture name (see Texture in texture.h for one with its size).
using GlTexture = GlObject<gl_object_detail::create_texture, gl_object_detail::delete_texture>;

}  // namespace accelviz
