#include "shader_instrumentation.hpp"
#include "messages.hpp"

#include <unistd.h>

#include <algorithm>
#include <mutex>
#include <optional>
#include <set>

#include "dump_registry.hpp"
#include "gl_calls.hpp"
#include "hook_table.hpp"
#include "options.hpp"
#include "pass_names.hpp"
#include "variants.hpp"

namespace glbudget {

namespace {
using instrument::Stage;

std::optional<Stage> stage_of(GLenum type) {
  switch (type) {
    case GL_VERTEX_SHADER:
      return Stage::vertex;
    case GL_TESS_CONTROL_SHADER:
      return Stage::tess_control;
    case GL_TESS_EVALUATION_SHADER:
      return Stage::tess_evaluation;
    case GL_GEOMETRY_SHADER:
      return Stage::geometry;
    case GL_FRAGMENT_SHADER:
      return Stage::fragment;
    default:
      return std::nullopt;  // compute: dispatches are not bound to counters
  }
}

bool has_calls(const GlCalls& g) {
  return g.GetStringi && g.GetShaderiv && g.GetProgramiv && g.GetProgramResourceIndex && g.ShaderStorageBlockBinding &&
         g.GenBuffers && g.DeleteBuffers && g.BufferData && g.BindBuffer && g.BindBufferBase && g.CopyBufferSubData &&
         g.MapBufferRange && g.UnmapBuffer && g.FenceSync && g.ClientWaitSync && g.DeleteSync;
}

std::unique_ptr<Instrumentation> make_instrumentation(const GlCaps& caps) {
  auto at_least = [&](int M, int m) { return caps.major > M || (caps.major == M && caps.minor >= m); };
  const GlCalls& g = gl();
  // Shader storage buffers: GL 4.3, GLES 3.1, or on older desktop contexts the extensions
  // (NVIDIA gives an app that asks for 3.3 exactly 3.3, with both extensions; the instrumented
  // shaders then name GL_ARB_shader_storage_buffer_object). Nothing is queried before this is
  // known, so no query can raise GL_INVALID_ENUM.
  const bool storage_buffers = caps.gles
                                   ? at_least(3, 1)
                                   : at_least(4, 3) || (has_extension(caps, "GL_ARB_shader_storage_buffer_object") &&
                                                        has_extension(caps, "GL_ARB_program_interface_query"));
  if (!storage_buffers || !has_calls(g)) return nullptr;
  GLint bindings = 0;
  g.GetIntegerv(GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS, &bindings);
  if (bindings < 1) return nullptr;
  // The highest binding: apps fill bindings from 0, so this one is the least likely in use.
  return std::make_unique<Instrumentation>(bindings - 1, extension_names());
}

void set_driver_source(GLuint shader, const std::string& source) {
  auto shader_source = reinterpret_cast<pfn_glShaderSource>(real_entry(kHook_glShaderSource));
  const GLchar* text = source.c_str();
  const GLint length = static_cast<GLint>(source.size());
  shader_source(shader, 1, &text, &length);
}

bool compile_status(GLuint shader) {
  GLint ok = 0;
  gl().GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  return ok == GL_TRUE;
}

bool link_status(GLuint program) {
  GLint ok = 0;
  gl().GetProgramiv(program, GL_LINK_STATUS, &ok);
  return ok == GL_TRUE;
}

// The app's shader compiled from the instrumented source if the driver accepts it, else
// from the app's own. Returns what the dump records.
instrument::InstrumentResult compile(Instrumentation& inst, GLuint shader, ShaderInfo& s, Stage stage,
                                     pfn_glCompileShader real) {
  instrument::InstrumentResult r =
      instrument::instrument_shader({{s.source}, stage, inst.binding(), inst.extensions()});
  bool instrumented = false;
  bool driver_has_ours = s.driver_source_instrumented;  // left by an earlier compile
  if (r.ok) {
    set_driver_source(shader, r.instrumented_source);
    driver_has_ours = true;
    real(shader);
    instrumented = compile_status(shader);
    if (!instrumented) {
      r.ok = false;
      r.error = "the driver does not compile the instrumented source";
    }
  }
  if (!instrumented) {
    if (driver_has_ours) set_driver_source(shader, s.source);
    real(shader);
  }
  s.driver_source_instrumented = instrumented;
  s.compiled_instrumented = instrumented;
  s.binding_in_source = r.binding_in_source;
  s.figures = r.figures;
  return r;
}
}  // namespace

Instrumentation* instrumentation_of(ContextState& c) {
  if (!options().instrument) return nullptr;
  if (!c.instrumentation_probed) {
    c.instrumentation_probed = true;
    c.instrumentation = make_instrumentation(c.caps);
    if (!c.instrumentation)
      say_once("no-ssbo", "instrumentation needs shader storage buffers (GL 4.3, GLES 3.1); off in this context");
  }
  return c.instrumentation.get();
}

void handle_glCompileShader(pfn_glCompileShader real, GLuint shader) {
  ContextState* c = current_context();
  Instrumentation* inst = c ? instrumentation_of(*c) : nullptr;
  if (!inst) return real(shader);
  std::lock_guard lock(c->group->mu);
  auto it = c->group->shaders.find(shader);
  std::optional<Stage> stage = it == c->group->shaders.end() ? std::nullopt : stage_of(it->second.stage);
  if (!stage) return real(shader);
  ShaderInfo& s = it->second;
  const std::string hash = hash_text(shader_hash(s.stage, s.source));
  instrument::InstrumentResult r = compile(*inst, shader, s, *stage, real);
  // A shader the app got wrong is the app's to report; ours are the ones that only we broke.
  if (!r.ok && compile_status(shader))
    say_once(hash, "shader " + hash + " (" + instrument::stage_name(*stage) + ") not instrumented: " + r.error +
                       "; it runs unchanged");
  dump_registry::add_shader({hash, *stage, s.source, std::move(r)});
}

void handle_glGetShaderSource(pfn_glGetShaderSource real, GLuint shader, GLsizei bufSize, GLsizei* length,
                              GLchar* source) {
  ContextState* c = current_context();
  if (c && c->instrumentation && bufSize > 0 && source) {
    std::lock_guard lock(c->group->mu);
    auto it = c->group->shaders.find(shader);
    if (it != c->group->shaders.end() && it->second.driver_source_instrumented) {
      // The app's source, not the instrumented one the driver holds.
      const std::string& text = it->second.source;
      const size_t n = std::min(text.size(), static_cast<size_t>(bufSize) - 1);
      text.copy(source, n);
      source[n] = '\0';
      if (length) *length = static_cast<GLsizei>(n);
      return;
    }
  }
  real(shader, bufSize, length, source);
}

void handle_glGetShaderiv(pfn_glGetShaderiv real, GLuint shader, GLenum pname, GLint* params) {
  real(shader, pname, params);
  ContextState* c = current_context();
  if (!c || !c->instrumentation || pname != GL_SHADER_SOURCE_LENGTH || !params) return;
  std::lock_guard lock(c->group->mu);
  auto it = c->group->shaders.find(shader);
  if (it != c->group->shaders.end() && it->second.driver_source_instrumented)
    *params = static_cast<GLint>(it->second.source.size() + 1);  // with its terminating null
}

void handle_glGetProgramBinary(pfn_glGetProgramBinary real, GLuint program, GLsizei bufSize, GLsizei* length,
                               GLenum* binaryFormat, void* binary) {
  ContextState* c = current_context();
  if (c && c->instrumentation) {
    std::lock_guard lock(c->group->mu);
    auto it = c->group->programs.find(program);
    if (it != c->group->programs.end() && it->second.instrumented) {
      // An app that caches binaries would keep our counters in a later run without glbudget,
      // writing to a binding nobody bound. An empty binary fails to load, and apps then
      // build from source, as they must when a driver update invalidates their cache.
      if (length) *length = 0;
      return;
    }
  }
  real(program, bufSize, length, binaryFormat, binary);
}

void after_link(ContextState& c, ShareGroup& g, GLuint program, ProgramInfo& info, pfn_glLinkProgram real) {
  info.instrumented = false;
  Instrumentation* inst = instrumentation_of(c);
  if (!inst) return;
  inst->buffers().forget(program);  // a new link counts afresh
  std::vector<ShaderInfo*> shaders;
  bool any_instrumented = false, needs_binding = false;
  for (GLuint id : info.shaders) {
    auto it = g.shaders.find(id);
    if (it == g.shaders.end()) continue;
    shaders.push_back(&it->second);
    any_instrumented |= it->second.compiled_instrumented;
    needs_binding |= it->second.compiled_instrumented && !it->second.binding_in_source;
  }
  const std::string hash = hash_text(info.pass);
  if (any_instrumented && link_status(program)) {
    if (needs_binding) {
      GLuint block = gl().GetProgramResourceIndex(program, GL_SHADER_STORAGE_BLOCK, instrument::kCounterBlockName);
      if (block != GL_INVALID_INDEX)
        gl().ShaderStorageBlockBinding(program, block, static_cast<GLuint>(inst->binding()));
    }
    info.instrumented = true;
  } else if (any_instrumented) {
    // Relink from the app's sources: the app must get the program it asked for. A shader whose
    // source the app has replaced since compiling is left alone (recompiling it would compile
    // what the app has not asked to compile).
    auto compile_shader = reinterpret_cast<pfn_glCompileShader>(real_entry(kHook_glCompileShader));
    for (GLuint id : info.shaders) {
      auto it = g.shaders.find(id);
      if (it == g.shaders.end() || !it->second.driver_source_instrumented) continue;
      set_driver_source(id, it->second.source);
      compile_shader(id);
      it->second.driver_source_instrumented = it->second.compiled_instrumented = false;
    }
    real(program);
    if (link_status(program))
      say_once(hash, "program " + hash + " not instrumented: the instrumented shaders do not link; it runs unchanged");
  }
  instrument::ProgramDump dump{hash, {}};
  for (const ShaderInfo* s : shaders)
    if (auto stage = stage_of(s->stage))
      dump.stages.push_back({*stage, hash_text(shader_hash(s->stage, s->source)), s->figures, std::nullopt});
  dump_registry::add_program(dump);
}

InstrumentedVariant instrument_variant(Instrumentation& inst, const std::vector<std::pair<GLenum, std::string>>& stages,
                                       const std::string& program_hash) {
  InstrumentedVariant out;
  out.dump.hash = program_hash;
  for (const auto& [type, source] : stages) {
    const std::optional<Stage> stage = stage_of(type);
    if (!stage) {
      out.sources.push_back(source);
      continue;
    }
    instrument::InstrumentResult r =
        instrument::instrument_shader({{source}, *stage, inst.binding(), inst.extensions()});
    out.sources.push_back(r.ok ? r.instrumented_source : source);
    out.any |= r.ok;
    out.needs_binding |= r.ok && !r.binding_in_source;
    const std::string shader = hash_text(shader_hash(type, source));
    out.dump.stages.push_back({*stage, shader, r.figures, std::nullopt});
    dump_registry::add_shader({shader, *stage, source, std::move(r)});
  }
  return out;
}

void after_variant_link(Instrumentation& inst, GLuint program, const InstrumentedVariant& variant) {
  inst.buffers().forget(program);
  if (variant.needs_binding) {
    GLuint block = gl().GetProgramResourceIndex(program, GL_SHADER_STORAGE_BLOCK, instrument::kCounterBlockName);
    if (block != GL_INVALID_INDEX) gl().ShaderStorageBlockBinding(program, block, static_cast<GLuint>(inst.binding()));
  }
  dump_registry::add_program(variant.dump);
}

void bind_counters(ContextState& c) {
  // Made here too: a context may draw programs another context of its share group built.
  Instrumentation* inst = instrumentation_of(c);
  if (!inst) return;
  std::lock_guard lock(c.group->mu);
  auto instrumented = [&](GLuint program) -> const ProgramInfo* {
    auto it = c.group->programs.find(program);
    return it != c.group->programs.end() && it->second.instrumented ? &it->second : nullptr;
  };
  if (c.program) {
    // A variant in the app's program's place counts under its own name, as the log names it.
    if (c.bound_variants) {
      const Variant& v = c.bound_variants->at(c.config);
      if (v.program) {
        if (v.instrumented) inst->buffers().bind(v.program, {v.dump_name});
        return;
      }
    }
    if (const ProgramInfo* p = instrumented(c.program)) inst->buffers().bind(c.program, {hash_text(p->pass)});
    return;
  }
  // A pipeline has one counter buffer; its stages write disjoint words, so each of its
  // programs is credited with the words of its own stages.
  auto it = c.pipeline_stages.find(c.pipeline);
  if (!c.pipeline || it == c.pipeline_stages.end()) return;
  std::vector<std::string> hashes;
  for (GLuint program : it->second)
    if (const ProgramInfo* p = instrumented(program)) {
      std::string hash = hash_text(p->pass);
      if (std::find(hashes.begin(), hashes.end(), hash) == hashes.end()) hashes.push_back(std::move(hash));
    }
  // Keyed by the pipeline and its programs: changing a stage's program starts a new count.
  uint64_t key = fnv1a_u64(c.pipeline, fnv1a("pipeline"));
  for (const std::string& hash : hashes) key = fnv1a(hash, key);
  if (!hashes.empty()) inst->buffers().bind(key, hashes);
}

void instrumentation_swap(ContextState& c) {
  if (c.instrumentation) c.instrumentation->buffers().poll(c.frame);
}

void instrumentation_release(ContextState& c) {
  if (c.instrumentation) c.instrumentation->buffers().read_all_now();
}

}  // namespace glbudget
