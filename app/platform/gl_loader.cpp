#include "app/platform/gl_loader.h"

namespace accelviz {

GlFunctions gl;

bool load_gl(GlProcLookup lookup, std::string* missing) {
    GlFunctions loaded;
    // Each entry: look up "gl" + name; a miss fails the whole load, so the
    // renderer never calls through a null pointer.
#define ACCELVIZ_GL_LOAD(type, name)                                        \
    loaded.name = reinterpret_cast<type>(lookup("gl" #name));               \
    if (!loaded.name) {                                                     \
        if (missing) *missing = "gl" #name;                                 \
        return false;                                                       \
    }
    ACCELVIZ_GL_FUNCTIONS(ACCELVIZ_GL_LOAD)
#undef ACCELVIZ_GL_LOAD
    // The compute entry points: optional (a lookup may hand out pointers for functions
    // the context does not provide, so the version decides).
    loaded.has_compute = true;
#define ACCELVIZ_GL_LOAD_OPTIONAL(type, name)                               \
    loaded.name = reinterpret_cast<type>(lookup("gl" #name));               \
    if (!loaded.name) loaded.has_compute = false;
    ACCELVIZ_GL_COMPUTE_FUNCTIONS(ACCELVIZ_GL_LOAD_OPTIONAL)
#undef ACCELVIZ_GL_LOAD_OPTIONAL
    GLint major = 0, minor = 0;
    loaded.GetIntegerv(GL_MAJOR_VERSION, &major);
    loaded.GetIntegerv(GL_MINOR_VERSION, &minor);
    if (major < 4 || (major == 4 && minor < 3)) loaded.has_compute = false;
    gl = loaded;
    return true;
}

std::string gl_description() {
    if (!gl.GetString) return {};
    auto text = [](GLenum name) {
        const GLubyte* s = gl.GetString(name);
        return s ? std::string(reinterpret_cast<const char*>(s)) : std::string("?");
    };
    return text(GL_VERSION) + ", " + text(GL_RENDERER);
}

}  // namespace accelviz
