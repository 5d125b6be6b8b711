// Shader and program life cycle: the sources that name a pass, and which pass is bound.
#include <algorithm>

#include "context_state.hpp"
#include "hooks_generated.hpp"
#include "pass_names.hpp"
#include "apply_gl.hpp"
#include "hook_table.hpp"
#include "governing.hpp"
#include "gl_calls.hpp"
#include "gl_errors.hpp"
#include "shader_instrumentation.hpp"
#include "subroutines.hpp"
#include "variant_dump.hpp"

namespace glbudget {

namespace {
std::string join_sources(GLsizei count, const GLchar* const* strings, const GLint* lengths) {
  std::string all;
  for (GLsizei i = 0; strings && i < count; ++i) {
    if (!strings[i]) continue;
    if (lengths && lengths[i] >= 0)
      all.append(strings[i], static_cast<size_t>(lengths[i]));
    else
      all.append(strings[i]);
  }
  return all;
}

void refresh_if_bound(ContextState* c) {
  if (!c) return;
  update_pass(*c);
  bind_counters(*c);
}

bool link_succeeded(GLuint program) {
  GLint ok = GL_FALSE;
  if (gl().GetProgramiv) gl().GetProgramiv(program, GL_LINK_STATUS, &ok);
  return ok == GL_TRUE;
}

bool app_coordinate_copies(const ContextState& c) { return c.targets && manifest_app_coordinates(); }

// The driver's extensions, for preprocessing as the driver does (read once per context).
const std::optional<std::vector<std::string>>& driver_extensions(ContextState& c) {
  if (!c.extensions && gl().GetStringi && c.caps.major >= 3) c.extensions = extension_names();
  return c.extensions;
}

// After the app's link: the manifest pass that claims the program, and its variants; where
// render targets may be scaled, its copy that sees the app's pixels in them. Caller holds the
// share group's lock.
void shadow_program(ContextState& c, ShareGroup& g, GLuint program, ProgramInfo& p,
                    std::vector<ShaderSource> sources = {}) {
  if (p.variants) {
    delete_variants(*p.variants);  // a relink replaces them: they were built from the old sources
    p.variants.reset();
  }
  p.manifest_pass = -1;
  p.app_space_refused.clear();
  // Instrumented runs (calibration, dumps) count the app's programs as they are.
  const bool app_coordinates = app_coordinate_copies(c) && !instrumentation_of(c);
  if (!manifest_has_programs() && !app_coordinates) return;
  for (GLuint s : p.shaders) {
    auto it = g.shaders.find(s);
    if (it != g.shaders.end()) sources.push_back({it->second.stage, it->second.source});
  }
  if (manifest_has_programs()) p.manifest_pass = match_pass(p.pass, sources);
  if (p.manifest_pass >= 0) {
    note_pass_matched(p.manifest_pass);
    g.has_matched = true;
  }
  if (p.manifest_pass < 0 && !app_coordinates) return;
  if (!link_succeeded(program)) return;  // the app's own failure: nothing to shadow
  p.variants = build_variants(program, p.pass, p.manifest_pass, sources, c.caps,
                              {p.attribute_bindings, p.frag_data_bindings}, instrumentation_of(c), app_coordinates,
                              app_coordinates ? driver_extensions(c) : std::nullopt, &p.app_space_refused);
  if (p.variants) g.has_variants = true;
  if (!p.app_space_refused.empty()) g.has_refused = true;
  if (p.manifest_pass < 0) return;
  // The governor sums a pass's programs, under whichever name a variant logs them.
  note_program_pass(p.pass, p.manifest_pass);
  if (p.variants)
    for (const Variant& v : p.variants->levels) note_program_pass(v.pass_hash, p.manifest_pass);
  std::vector<DrawnProgram> drawn_at_level(active_manifest().passes[static_cast<size_t>(p.manifest_pass)].levels.size(),
                                           {p.pass, hash_text(p.pass)});
  if (p.variants)
    for (size_t l = 0; l < p.variants->levels.size() && l < drawn_at_level.size(); ++l)
      if (const Variant& v = p.variants->levels[l]; v.program) drawn_at_level[l] = {v.pass_hash, v.dump_name};
  dump_pass_programs(p.manifest_pass, drawn_at_level);
}
}  // namespace

namespace {
// Bits of GL_{VERTEX,FRAGMENT,GEOMETRY,TESS_CONTROL,TESS_EVALUATION,COMPUTE}_SHADER_BIT, and
// the matching stage names for glGetProgramPipelineiv.
const GLbitfield kStageBits[6] = {GL_VERTEX_SHADER_BIT,       GL_FRAGMENT_SHADER_BIT,        GL_GEOMETRY_SHADER_BIT,
                                  GL_TESS_CONTROL_SHADER_BIT, GL_TESS_EVALUATION_SHADER_BIT, GL_COMPUTE_SHADER_BIT};
constexpr int kFragmentSlot = 1;  // of the arrays above
const GLenum kStageNames[6] = {GL_VERTEX_SHADER,       GL_FRAGMENT_SHADER,        GL_GEOMETRY_SHADER,
                               GL_TESS_CONTROL_SHADER, GL_TESS_EVALUATION_SHADER, GL_COMPUTE_SHADER};

std::shared_ptr<const VariantSet> variants_of(ContextState& c, GLuint program) {
  if (!program || !c.group->has_variants) return nullptr;
  std::lock_guard lock(c.group->mu);
  auto it = c.group->programs.find(program);
  return it == c.group->programs.end() ? nullptr : it->second.variants;
}

// The program the driver must hold where the app put `program`, under the configuration.
GLuint real_stage_program(ContextState& c, GLuint program) {
  auto v = variants_of(c, program);
  return v ? v->program_for(c.config) : program;
}

// A program in app coordinates drawing (apply/app_space_uniforms.hpp): every draw is hooked.
void hook_every_draw_of_copies(ContextState& c) {
  auto any = [](const std::shared_ptr<const VariantSet>& set) {
    if (!set) return false;
    for (const Variant& v : set->levels)
      if (v.program && v.app_space.any()) return true;
    return false;
  };
  if (c.counter && c.targets)
    c.counter->set_every_draw_hooked(any(c.program ? c.bound_variants : c.pipeline_fragment_variants));
}

// The manifest pass a pipeline's draws belong to: that of its fragment stage's program, else of
// the first other stage's that matched one; -1 for none.
int pipeline_manifest_pass(ContextState& c, const std::array<GLuint, 6>& stages) {
  std::lock_guard lock(c.group->mu);
  auto pass_of = [&](GLuint program) {
    auto it = program ? c.group->programs.find(program) : c.group->programs.end();
    return it == c.group->programs.end() ? -1 : it->second.manifest_pass;
  };
  if (const int pass = pass_of(stages[kFragmentSlot]); pass >= 0) return pass;
  for (GLuint program : stages)
    if (const int pass = pass_of(program); pass >= 0) return pass;
  return -1;
}

void update_pipeline_uniforms(ContextState& c) {
  c.pipeline_uniform_variants.reset();
  c.pipeline_fragment_variants.reset();
  if (c.program || !c.pipeline) return;
  auto it = c.pipeline_active.find(c.pipeline);
  if (it != c.pipeline_active.end()) c.pipeline_uniform_variants = variants_of(c, it->second);
  auto stages = c.pipeline_stages.find(c.pipeline);
  if (stages != c.pipeline_stages.end()) c.pipeline_fragment_variants = variants_of(c, stages->second[kFragmentSlot]);
  // Its draws are the pass's: the targets it scales ("self"), the passes a probe frame saw.
  c.manifest_pass = stages == c.pipeline_stages.end() ? -1 : pipeline_manifest_pass(c, stages->second);
  hook_every_draw_of_copies(c);
}
}  // namespace

bool shadows_programs(const ContextState& c) { return manifest_has_programs() || app_coordinate_copies(c); }

void bind_program(ContextState& c) {
  std::shared_ptr<const VariantSet> variants;
  int pass = -1;
  c.app_space_refused = false;
  if (c.program && (c.group->has_variants || c.group->has_refused || c.group->has_matched)) {
    std::lock_guard lock(c.group->mu);
    auto it = c.group->programs.find(c.program);
    if (it != c.group->programs.end()) {
      variants = it->second.variants;
      pass = it->second.manifest_pass;
      c.app_space_refused = !it->second.app_space_refused.empty();
    }
  }
  c.bound_variants = std::move(variants);
  c.manifest_pass = pass;
  hook_every_draw_of_copies(c);
  const GLuint wanted = c.bound_variants ? c.bound_variants->program_for(c.config) : c.program;
  if (wanted != c.real_program) {
    agl().UseProgram(wanted);
    c.real_program = wanted;
    reapply_subroutines(c);  // GL reset the subroutine selections
  }
}

namespace {
// Deletes, for real, a program whose deletion waited for the app to stop using it.
void finish_pending_delete(ContextState& c, GLuint program) {
  std::lock_guard lock(c.group->mu);
  auto it = c.group->programs.find(program);
  if (it == c.group->programs.end() || !it->second.delete_pending) return;
  agl().DeleteProgram(program);
  if (it->second.variants) delete_variants(*it->second.variants);
  c.group->programs.erase(it);
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
    const OwnGlWork own(*c);  // instrumenting and building variants: the errors the app's link raised stay its
    after_link(*c, *c->group, program, p, real);
    shadow_program(*c, *c->group, program, p);
  }
  {
    // A program whose relink failed cannot be bound: what that raises is the shim's, not the app's.
    const OwnGlWork own(*c);
    if (c->program == program) bind_program(*c);
    if (!c->pipeline_stages.empty()) {  // the relinked program's new variants into the stages that hold it
      bind_pipeline_stages(*c);
      update_pipeline_uniforms(*c);
    }
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
    const std::string source = join_sources(count, strings, nullptr);
    p.pass = program_hash({shader_hash(type, source)});
    p.linked = true;
    // No shader objects to hook: the variants are built from the strings themselves.
    const OwnGlWork own(*c);
    shadow_program(*c, *c->group, program, p, {{type, source}});
  }
  return program;
}

void handle_glDeleteProgram(pfn_glDeleteProgram real, GLuint program) {
  ContextState* c = current_context();
  if (c && program && c->program == program && c->group->has_variants) {
    // GL keeps a program in use alive until it is unbound. The driver may have (or, after a
    // switch, get) a variant bound in its place and would then delete it at once: the real
    // delete waits until the app stops using it.
    std::lock_guard lock(c->group->mu);
    auto it = c->group->programs.find(program);
    if (it != c->group->programs.end()) {
      it->second.delete_pending = true;
      return;
    }
  }
  real(program);
  if (!c || !program) return;
  // GL keeps a program in use alive until it is unbound; so do we.
  if (c->program == program) return;
  std::lock_guard lock(c->group->mu);
  auto it = c->group->programs.find(program);
  if (it == c->group->programs.end()) return;
  if (it->second.variants) delete_variants(*it->second.variants);
  c->group->programs.erase(it);
}

void handle_glUseProgram(pfn_glUseProgram real, GLuint program) {
  real(program);
  ContextState* c = current_context();
  if (!c) return;
  const GLuint previous = c->program;
  c->program = program;
  c->real_program = program;
  bind_program(*c);  // a variant in the app's program's place, when the configuration says so
  update_pipeline_uniforms(*c);
  if (previous && previous != program) finish_pending_delete(*c, previous);
  update_pass(*c);
  bind_counters(*c);
}

void handle_glBindAttribLocation(pfn_glBindAttribLocation real, GLuint program, GLuint index, const GLchar* name) {
  real(program, index, name);
  ContextState* c = current_context();
  if (!c || !name || !shadows_programs(*c)) return;
  std::lock_guard lock(c->group->mu);
  auto& bindings = c->group->programs[program].attribute_bindings;
  std::erase_if(bindings, [&](const auto& b) { return b.first == name; });
  bindings.emplace_back(name, index);
}

namespace {

// A fragment output's location bound before the link, replayed onto the program's variants.
void remember_frag_data_binding(GLuint program, GLuint color, GLuint index, const GLchar* name) {
  ContextState* c = current_context();
  if (!c || !name || !shadows_programs(*c)) return;
  std::lock_guard lock(c->group->mu);
  auto& bindings = c->group->programs[program].frag_data_bindings;
  std::erase_if(bindings, [&](const auto& b) { return b.first == name; });
  bindings.emplace_back(name, std::make_pair(color, index));
}

}  // namespace

void handle_glBindFragDataLocationIndexed(pfn_glBindFragDataLocationIndexed real, GLuint program, GLuint colorNumber,
                                          GLuint index, const GLchar* name) {
  real(program, colorNumber, index, name);
  remember_frag_data_binding(program, colorNumber, index, name);
}

void handle_glBindFragDataLocation(pfn_glBindFragDataLocation real, GLuint program, GLuint color, const GLchar* name) {
  real(program, color, name);
  remember_frag_data_binding(program, color, 0u, name);
}

void handle_glUniformBlockBinding(pfn_glUniformBlockBinding real, GLuint program, GLuint index, GLuint binding) {
  real(program, index, binding);
  ContextState* c = current_context();
  if (!c || !c->group->has_variants) return;
  std::lock_guard lock(c->group->mu);
  auto it = c->group->programs.find(program);
  if (it != c->group->programs.end() && it->second.variants)
    forward_block_binding(*it->second.variants, index, binding, false);
}

void handle_glShaderStorageBlockBinding(pfn_glShaderStorageBlockBinding real, GLuint program, GLuint index,
                                        GLuint binding) {
  real(program, index, binding);
  ContextState* c = current_context();
  if (!c || !c->group->has_variants) return;
  std::lock_guard lock(c->group->mu);
  auto it = c->group->programs.find(program);
  if (it != c->group->programs.end() && it->second.variants)
    forward_block_binding(*it->second.variants, index, binding, true);
}

void handle_glBindProgramPipeline(pfn_glBindProgramPipeline real, GLuint pipeline) {
  real(pipeline);
  ContextState* c = current_context();
  if (!c) return;
  c->pipeline = pipeline;
  update_pipeline_uniforms(*c);
  update_pass(*c);
  bind_counters(*c);
}

void bind_pipeline_stages(ContextState& c) {
  if (!c.group->has_variants) return;
  auto use_stages = reinterpret_cast<pfn_glUseProgramStages>(real_entry(kHook_glUseProgramStages));
  for (auto& [pipeline, app] : c.pipeline_stages) {
    auto& real = c.pipeline_real_stages[pipeline];
    for (int i = 0; i < 6; ++i) {
      const GLuint wanted = real_stage_program(c, app[i]);
      if (wanted == real[i]) continue;
      if (use_stages) use_stages(pipeline, kStageBits[i], wanted);
      real[i] = wanted;
    }
  }
}

void handle_glUseProgramStages(pfn_glUseProgramStages real, GLuint pipeline, GLbitfield stages, GLuint program) {
  ContextState* c = current_context();
  if (!c) return real(pipeline, stages, program);
  // Each stage the call sets holds the variant the configuration asks for; stages of one call
  // share one program, and so one variant.
  const GLuint real_program = real_stage_program(*c, program);
  real(pipeline, stages, real_program);
  auto& slots = c->pipeline_stages[pipeline];
  auto& real_slots = c->pipeline_real_stages[pipeline];
  for (int i = 0; i < 6; ++i)
    if (stages & kStageBits[i]) {
      slots[i] = program;
      real_slots[i] = real_program;
    }
  if (c->pipeline == pipeline) {
    update_pipeline_uniforms(*c);
    refresh_if_bound(c);
  }
}

void handle_glActiveShaderProgram(pfn_glActiveShaderProgram real, GLuint pipeline, GLuint program) {
  real(pipeline, program);  // the app's program: glbudget's fan-out reaches its variants
  ContextState* c = current_context();
  if (!c) return;
  c->pipeline_active[pipeline] = program;
  update_pipeline_uniforms(*c);
}

// The app's programs, never the variants glbudget put in the stages.
void handle_glGetProgramPipelineiv(pfn_glGetProgramPipelineiv real, GLuint pipeline, GLenum pname, GLint* params) {
  real(pipeline, pname, params);
  ContextState* c = current_context();
  if (!c || !params) return;
  if (pname == GL_ACTIVE_PROGRAM) {
    auto it = c->pipeline_active.find(pipeline);
    if (it != c->pipeline_active.end()) *params = static_cast<GLint>(it->second);
    return;
  }
  auto it = c->pipeline_stages.find(pipeline);
  if (it == c->pipeline_stages.end()) return;
  for (int i = 0; i < 6; ++i)
    if (pname == kStageNames[i]) *params = static_cast<GLint>(it->second[i]);
}

}  // namespace glbudget
