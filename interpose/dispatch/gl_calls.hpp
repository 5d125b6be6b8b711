// The GL entry points the shim itself calls, resolved once per process. The shim calls
// only these, and only in ways that cannot raise a GL error (so the app's glGetError never
// sees one of ours). It calls glGetError only with the app's pending errors moved aside
// (state/gl_errors.hpp), around work that can fail (building variants).
#pragma once
#include <string>
#include <vector>

#include "gl_types.hpp"

namespace glbudget {

struct GlCalls {
  const GLubyte*(APIENTRYP GetString)(GLenum) = nullptr;
  PFNGLGETSTRINGIPROC GetStringi = nullptr;
  void(APIENTRYP GetIntegerv)(GLenum, GLint*) = nullptr;
  PFNGLGENQUERIESPROC GenQueries = nullptr;
  PFNGLDELETEQUERIESPROC DeleteQueries = nullptr;
  PFNGLBEGINQUERYPROC BeginQuery = nullptr;
  PFNGLENDQUERYPROC EndQuery = nullptr;
  PFNGLQUERYCOUNTERPROC QueryCounter = nullptr;
  PFNGLGETQUERYOBJECTUIVPROC GetQueryObjectuiv = nullptr;
  PFNGLGETQUERYOBJECTUI64VPROC GetQueryObjectui64v = nullptr;
  PFNGLBINDBUFFERPROC BindBuffer = nullptr;
  PFNGLGETSHADERIVPROC GetShaderiv = nullptr;
  void(APIENTRYP Flush)(void) = nullptr;
  GLenum(APIENTRYP GetError)(void) = nullptr;
  // Shader instrumentation (GLBUDGET_INSTRUMENT / GLBUDGET_DUMP).
  PFNGLGETPROGRAMIVPROC GetProgramiv = nullptr;
  PFNGLGETPROGRAMRESOURCEINDEXPROC GetProgramResourceIndex = nullptr;
  PFNGLSHADERSTORAGEBLOCKBINDINGPROC ShaderStorageBlockBinding = nullptr;
  PFNGLGENBUFFERSPROC GenBuffers = nullptr;
  PFNGLDELETEBUFFERSPROC DeleteBuffers = nullptr;
  PFNGLBUFFERDATAPROC BufferData = nullptr;
  PFNGLBINDBUFFERBASEPROC BindBufferBase = nullptr;
  PFNGLCOPYBUFFERSUBDATAPROC CopyBufferSubData = nullptr;
  PFNGLMAPBUFFERRANGEPROC MapBufferRange = nullptr;
  PFNGLUNMAPBUFFERPROC UnmapBuffer = nullptr;
  PFNGLFENCESYNCPROC FenceSync = nullptr;
  PFNGLCLIENTWAITSYNCPROC ClientWaitSync = nullptr;
  PFNGLDELETESYNCPROC DeleteSync = nullptr;
};

extern GlCalls g_gl;

// Resolves what is still missing; returns false if the basics (GetString, GetIntegerv) are.
// Called under the context registry's lock when a context is first made current.
bool load_gl_calls();

inline const GlCalls& gl() { return g_gl; }

// The current context's extensions, by index (glGetStringi: GL 3.0, GLES 3.0; empty before).
std::vector<std::string> extension_names();

}  // namespace glbudget
