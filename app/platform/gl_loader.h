#pragma once
/// Our own OpenGL 3.3 core loader: a table of function pointers filled through a
/// lookup callback (glfwGetProcAddress for a window, OSMesaGetProcAddress for
/// headless rendering).
///
/// Why not a packaged loader: they all resolve through the system libGL.so.1
/// (glvnd), which cannot see an OSMesa context (see docs/PLATFORM.md, "The GL
/// loader trap"). This header never includes <GL/gl.h> or <GL/osmesa.h>; only
/// the typedefs and constants of <GL/glcorearb.h>, which declares no functions.
///
/// Use: `gl.Clear(GL_COLOR_BUFFER_BIT)`. The table is filled by
/// GlContext::make_current() (a GLFW window or an OSMesa buffer), so it always
/// matches the context that is current on this thread.

#include <GL/glcorearb.h>

#include "app/platform/gl_lookup.h"

namespace accelviz {

/// Every GL entry point the renderer and the ImGui renderer use, as
/// X(typedef, name-without-"gl"). Add a function here and it is loaded.
#define ACCELVIZ_GL_FUNCTIONS(X)                                   \
    /* state */                                                     \
    X(PFNGLGETERRORPROC, GetError)                                  \
    X(PFNGLGETSTRINGPROC, GetString)                                \
    X(PFNGLGETINTEGERVPROC, GetIntegerv)                            \
    X(PFNGLENABLEPROC, Enable)                                      \
    X(PFNGLDISABLEPROC, Disable)                                    \
    X(PFNGLVIEWPORTPROC, Viewport)                                  \
    X(PFNGLSCISSORPROC, Scissor)                                    \
    X(PFNGLCLEARCOLORPROC, ClearColor)                              \
    X(PFNGLCLEARDEPTHPROC, ClearDepth)                              \
    X(PFNGLCLEARPROC, Clear)                                        \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)                        \
    X(PFNGLDEPTHFUNCPROC, DepthFunc)                                \
    X(PFNGLDEPTHMASKPROC, DepthMask)                                \
    X(PFNGLCOLORMASKPROC, ColorMask)                                \
    X(PFNGLPOLYGONOFFSETPROC, PolygonOffset)                        \
    X(PFNGLLINEWIDTHPROC, LineWidth)                                \
    X(PFNGLPIXELSTOREIPROC, PixelStorei)                            \
    X(PFNGLREADPIXELSPROC, ReadPixels)                              \
    X(PFNGLFINISHPROC, Finish)                                      \
    /* buffers and vertex arrays */                                 \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                              \
    X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                        \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                              \
    X(PFNGLBUFFERDATAPROC, BufferData)                              \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                        \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                    \
    X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)              \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                    \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)    \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)            \
    X(PFNGLVERTEXATTRIBDIVISORPROC, VertexAttribDivisor)            \
    /* drawing */                                                   \
    X(PFNGLDRAWARRAYSPROC, DrawArrays)                              \
    X(PFNGLDRAWELEMENTSPROC, DrawElements)                          \
    X(PFNGLDRAWARRAYSINSTANCEDPROC, DrawArraysInstanced)            \
    X(PFNGLDRAWELEMENTSINSTANCEDPROC, DrawElementsInstanced)        \
    X(PFNGLDRAWELEMENTSBASEVERTEXPROC, DrawElementsBaseVertex)      \
    /* textures */                                                  \
    X(PFNGLGENTEXTURESPROC, GenTextures)                            \
    X(PFNGLDELETETEXTURESPROC, DeleteTextures)                      \
    X(PFNGLBINDTEXTUREPROC, BindTexture)                            \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                        \
    X(PFNGLTEXIMAGE2DPROC, TexImage2D)                              \
    X(PFNGLCOPYTEXSUBIMAGE2DPROC, CopyTexSubImage2D)                \
    X(PFNGLTEXPARAMETERIPROC, TexParameteri)                        \
    /* shaders */                                                   \
    X(PFNGLCREATESHADERPROC, CreateShader)                          \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                          \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                        \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                            \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                  \
    X(PFNGLDELETESHADERPROC, DeleteShader)                          \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                        \
    X(PFNGLATTACHSHADERPROC, AttachShader)                          \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                            \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                          \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                \
    X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                        \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                              \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)              \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                                \
    X(PFNGLUNIFORM1FPROC, Uniform1f)                                \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                                \
    X(PFNGLUNIFORM3FPROC, Uniform3f)                                \
    X(PFNGLUNIFORM4FPROC, Uniform4f)                                \
    X(PFNGLUNIFORMMATRIX4FVPROC, UniformMatrix4fv)

/// OpenGL 4.3's compute shaders and storage buffers (the GPU ray caster): loaded when
/// the context has them, not required (the rest of the program needs 3.3 only).
#define ACCELVIZ_GL_COMPUTE_FUNCTIONS(X)                           \
    X(PFNGLDISPATCHCOMPUTEPROC, DispatchCompute)                    \
    X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                      \
    X(PFNGLMEMORYBARRIERPROC, MemoryBarrier)                        \
    X(PFNGLGETBUFFERSUBDATAPROC, GetBufferSubData)                  \
    X(PFNGLUNIFORM2IPROC, Uniform2i)

/// The function table. A null entry means "not loaded yet".
struct GlFunctions {
#define ACCELVIZ_GL_DECLARE(type, name) type name = nullptr;
    ACCELVIZ_GL_FUNCTIONS(ACCELVIZ_GL_DECLARE)
    ACCELVIZ_GL_COMPUTE_FUNCTIONS(ACCELVIZ_GL_DECLARE)
#undef ACCELVIZ_GL_DECLARE
    /// The context is OpenGL 4.3 or later and every compute entry point was found.
    bool has_compute = false;
};

/// The table for the current context. GL is used from one thread only (the UI
/// thread, or the thread that renders headless).
extern GlFunctions gl;

}  // namespace accelviz
