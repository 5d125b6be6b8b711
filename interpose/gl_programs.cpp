// Shader and program life cycle: the sources that name a pass, and which pass is bound.
#include <algorithm>

#include "context_state.h"
#include "hooks_generated.h"
#include "pass_names.h"
#include "shader_instrumentation.h"

namespace glbudget {

namespace {
std::string join_sources(GLsizei count, const GLchar* const* strings, const GLint* lengths) {
  std::string all;
  for (GLsizei i = 0; strings && i < count; ++i) {
    if (!strings[i]) continue;
    if (lengths && lengths[i] >= 0) all.append(strings[i], static_cast<size_t>(lengths[i]));
    else all.append(strings[i]);
  }
  return all;
}

void refresh_if_bound(ContextState* c) {
  if (!c) return;
  update_pass(*c);
  bind_counters(*c);
}
}  // namespace

GLuint handle_glCreateShader(pfn_glCreateShader real, GLenum type) {
  GLuint shader = real(type);
  ContextState* c = current_context();
  if (c && shader) {
    std::lock_guard lock(c->group->mu);
    ShaderInfo info;
    info.stage = type;
    c->group->shaders[shader] = std::move(info);
  }
  return shader;
}

void handle_glShaderSource(pfn_glShaderSource real, GLuint shader, GLsizei count, const GLchar* const* string,
                           const GLint* length) {
  real(shader, count, string, length);
  ContextState* c = current_context();
  if (!c || count < 0) return;
  std::lock_guard lock(c->group->mu);
  auto it = c->group->shaders.find(shader);
  if (it == c->group->shaders.end()) return;
  it->second.source = join_sources(count, string, length);
  it->second.driver_source_instrumented = false;  // the driver holds the app's source again
}

void handle_glDeleteShader(pfn_glDeleteShader real, GLuint shader) {
  real(shader);
  ContextState* c = current_context();
  if (!c) return;
  // GL defers deleting an attached shader, and a relink may still need its source: keep it
  // while any program has it attached.
  std::lock_guard lock(c->group->mu);
  for (auto& [id, p] : c->group->programs)
    if (std::find(p.shaders.begin(), p.shaders.end(), shader) != p.shaders.end()) return;
  c->group->shaders.erase(shader);
}

void handle_glAttachShader(pfn_glAttachShader real, GLuint program, GLuint shader) {
  real(program, shader);
  ContextState* c = current_context();
  if (!c) return;
  std::lock_guard lock(c->group->mu);
  auto& shaders = c->group->programs[program].shaders;
  if (std::find(shaders.begin(), shaders.end(), shader) == shaders.end()) shaders.push_back(shader);
}

void handle_glDetachShader(pfn_glDetachShader real, GLuint program, GLuint shader) {
  real(program, shader);
  ContextState* c = current_context();
  if (!c) return;
  std::lock_guard lock(c->group->mu);
  auto it = c->group->programs.find(program);
  if (it == c->group->programs.end()) return;
  auto& shaders = it->second.shaders;
  shaders.erase(std::remove(shaders.begin(), shaders.end(), shader), shaders.end());
}

void handle_glLinkProgram(pfn_glLinkProgram real, GLuint program) {
  real(program);
  ContextState* c = current_context();
  if (!c) return;
  {
    std::lock_guard lock(c->group->mu);
    ProgramInfo& p = c->group->programs[program];
    std::vector<uint64_t> hashes;
    for (GLuint s : p.shaders) {
      auto it = c->group->shaders.find(s);
      if (it != c->group->shaders.end()) hashes.push_back(shader_hash(it->second.stage, it->second.source));
    }
    p.pass = program_hash(std::move(hashes));
    p.linked = true;
    after_link(*c, *c->group, program, p, real);
  }
  refresh_if_bound(c);
}

GLuint handle_glCreateShaderProgramv(pfn_glCreateShaderProgramv real, GLenum type, GLsizei count,
                                     const GLchar* const* strings) {
  GLuint program = real(type, count, strings);
  ContextState* c = current_context();
  if (c && program) {
    std::lock_guard lock(c->group->mu);
    ProgramInfo& p = c->group->programs[program];
    p.pass = program_hash({shader_hash(type, join_sources(count, strings, nullptr))});
    p.linked = true;
  }
  return program;
}

void handle_glDeleteProgram(pfn_glDeleteProgram real, GLuint program) {
  real(program);
  ContextState* c = current_context();
  if (!c || !program) return;
  // GL keeps a program in use alive until it is unbound; so do we.
  if (c->program == program) return;
  std::lock_guard lock(c->group->mu);
  c->group->programs.erase(program);
}

void handle_glUseProgram(pfn_glUseProgram real, GLuint program) {
  real(program);
  ContextState* c = current_context();
  if (!c) return;
  c->program = program;
  update_pass(*c);
  bind_counters(*c);
}

void handle_glBindProgramPipeline(pfn_glBindProgramPipeline real, GLuint pipeline) {
  real(pipeline);
  ContextState* c = current_context();
  if (!c) return;
  c->pipeline = pipeline;
  update_pass(*c);
  bind_counters(*c);
}

void handle_glUseProgramStages(pfn_glUseProgramStages real, GLuint pipeline, GLbitfield stages, GLuint program) {
  real(pipeline, stages, program);
  ContextState* c = current_context();
  if (!c) return;
  // Bits of GL_{VERTEX,FRAGMENT,GEOMETRY,TESS_CONTROL,TESS_EVALUATION,COMPUTE}_SHADER_BIT.
  static const GLbitfield kBits[6] = {GL_VERTEX_SHADER_BIT, GL_FRAGMENT_SHADER_BIT, GL_GEOMETRY_SHADER_BIT,
                                      GL_TESS_CONTROL_SHADER_BIT, GL_TESS_EVALUATION_SHADER_BIT,
                                      GL_COMPUTE_SHADER_BIT};
  auto& slots = c->pipeline_stages[pipeline];
  for (int i = 0; i < 6; ++i)
    if (stages & kBits[i]) slots[i] = program;
  if (c->pipeline == pipeline) refresh_if_bound(c);
}

}  // namespace glbudget
