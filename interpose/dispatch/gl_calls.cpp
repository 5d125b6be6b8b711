#include "gl_calls.hpp"

#include "hook_table.hpp"

namespace glbudget {

GlCalls g_gl;

namespace {
template <typename T>
void load_one(T& fn, const char* name) {
  if (!fn) fn = reinterpret_cast<T>(resolve_gl(name));
}
}  // namespace

bool load_gl_calls() {
  GlCalls& g = g_gl;
  load_one(g.GetString, "glGetString");
  load_one(g.GetStringi, "glGetStringi");
  load_one(g.GetIntegerv, "glGetIntegerv");
  load_one(g.GenQueries, "glGenQueries");
  load_one(g.DeleteQueries, "glDeleteQueries");
  load_one(g.BeginQuery, "glBeginQuery");
  load_one(g.EndQuery, "glEndQuery");
  load_one(g.QueryCounter, "glQueryCounter");
  load_one(g.GetQueryObjectuiv, "glGetQueryObjectuiv");
  load_one(g.GetQueryObjectui64v, "glGetQueryObjectui64v");
  load_one(g.BindBuffer, "glBindBuffer");
  load_one(g.GetShaderiv, "glGetShaderiv");
  load_one(g.Flush, "glFlush");
  load_one(g.GetError, "glGetError");
  load_one(g.GetProgramiv, "glGetProgramiv");
  load_one(g.GetProgramResourceIndex, "glGetProgramResourceIndex");
  load_one(g.ShaderStorageBlockBinding, "glShaderStorageBlockBinding");
  load_one(g.GenBuffers, "glGenBuffers");
  load_one(g.DeleteBuffers, "glDeleteBuffers");
  load_one(g.BufferData, "glBufferData");
  load_one(g.BindBufferBase, "glBindBufferBase");
  load_one(g.CopyBufferSubData, "glCopyBufferSubData");
  load_one(g.MapBufferRange, "glMapBufferRange");
  load_one(g.UnmapBuffer, "glUnmapBuffer");
  load_one(g.FenceSync, "glFenceSync");
  load_one(g.ClientWaitSync, "glClientWaitSync");
  load_one(g.DeleteSync, "glDeleteSync");
  return g.GetString && g.GetIntegerv;
}

std::vector<std::string> extension_names() {
  std::vector<std::string> names;
  if (!g_gl.GetStringi) return names;
  GLint count = 0;
  g_gl.GetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i)
    if (auto e = reinterpret_cast<const char*>(g_gl.GetStringi(GL_EXTENSIONS, static_cast<GLuint>(i))))
      names.emplace_back(e);
  return names;
}

}  // namespace glbudget
