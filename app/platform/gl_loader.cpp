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
