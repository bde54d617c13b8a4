#pragma once
/// The part of the GL loader that needs no GL headers, for the context files:
/// osmesa_context.cpp includes <GL/osmesa.h> (and so <GL/gl.h>), which would
/// hide <GL/glcorearb.h>'s function-pointer typedefs if both met in one file.

#include <string>

namespace accelviz {

/// Looks up one function by its full name ("glClear"); null if unknown.
using GlProcLookup = void* (*)(const char* name);

/// Fills the `gl` table (gl_loader.h) through `lookup`. Returns false and names
/// the first function that could not be found in `missing` (the context is then
/// unusable).
bool load_gl(GlProcLookup lookup, std::string* missing);

/// "4.5 (Core Profile) Mesa 22.3.6, llvmpipe (LLVM 15.0.6, 256 bits)", through
/// the loaded table (empty if nothing is loaded).
std::string gl_description();

}  // namespace accelviz
