// The GL functions the probes use, as a table: each probe fills it its own way (direct
// linking, GLEW, dlsym, GetProcAddress), which is exactly what the probes exist to vary.
#pragma once
#include <GL/gl.h>
#include <GL/glext.h>

// clang-format off
#define PROBE_GL_FUNCTIONS(X)                                                         \
  X(PFNGLCREATESHADERPROC, CreateShader) X(PFNGLSHADERSOURCEPROC, ShaderSource)       \
  X(PFNGLCOMPILESHADERPROC, CompileShader) X(PFNGLGETSHADERIVPROC, GetShaderiv)       \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog) X(PFNGLCREATEPROGRAMPROC, CreateProgram) \
  X(PFNGLATTACHSHADERPROC, AttachShader) X(PFNGLLINKPROGRAMPROC, LinkProgram)         \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv) X(PFNGLUSEPROGRAMPROC, UseProgram)           \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation) X(PFNGLUNIFORM4FPROC, Uniform4f) \
  X(PFNGLGENBUFFERSPROC, GenBuffers) X(PFNGLBINDBUFFERPROC, BindBuffer)               \
  X(PFNGLBUFFERDATAPROC, BufferData) X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)     \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                                        \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                                \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)                        \
  X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation)                                  \
  X(decltype(&::glDrawArrays), DrawArrays) X(decltype(&::glClear), Clear)                          \
  X(decltype(&::glClearColor), ClearColor) X(decltype(&::glViewport), Viewport)                   \
  X(decltype(&::glReadPixels), ReadPixels) X(decltype(&::glGetError), GetError)                   \
  X(decltype(&::glFinish), Finish) X(decltype(&::glGetString), GetString)                         \
  X(PFNGLGENQUERIESPROC, GenQueries) X(PFNGLBEGINQUERYPROC, BeginQuery)               \
  X(PFNGLENDQUERYPROC, EndQuery) X(PFNGLGETQUERYOBJECTUIVPROC, GetQueryObjectuiv)     \
  X(PFNGLGETQUERYIVPROC, GetQueryiv) X(decltype(&::glEnable), Enable)                       \
  X(decltype(&::glDisable), Disable) X(decltype(&::glGetIntegerv), GetIntegerv)
// clang-format on

struct GlFns {
#define PROBE_DECLARE(type, name) type name = nullptr;
  PROBE_GL_FUNCTIONS(PROBE_DECLARE)
#undef PROBE_DECLARE
  // Fills every entry from `lookup("gl" + name)`; returns the first missing name or null.
  template <typename Lookup>
  const char* load(Lookup lookup) {
#define PROBE_LOAD(type, name)                       \
  name = reinterpret_cast<type>(lookup("gl" #name)); \
  if (!name) return "gl" #name;
    PROBE_GL_FUNCTIONS(PROBE_LOAD)
#undef PROBE_LOAD
    return nullptr;
  }
};
