#include "variants.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <limits>
#include <map>
#include <mutex>
#include <set>

#include "apply_gl.hpp"
#include "gl_calls.hpp"
#include "gl_errors.hpp"
#include "messages.hpp"
#include "options.hpp"
#include "glbudget/instrument/app_space.hpp"
#include "glbudget/instrument/defines.hpp"
#include "pass_names.hpp"
#include "shader_instrumentation.hpp"
#include "uniform_values.hpp"

namespace glbudget {

namespace {

std::optional<manifest::Stage> manifest_stage(GLenum stage) {
  switch (stage) {
    case GL_VERTEX_SHADER:
      return manifest::Stage::vertex;
    case GL_TESS_CONTROL_SHADER:
      return manifest::Stage::tess_control;
    case GL_TESS_EVALUATION_SHADER:
      return manifest::Stage::tess_evaluation;
    case GL_GEOMETRY_SHADER:
      return manifest::Stage::geometry;
    case GL_FRAGMENT_SHADER:
      return manifest::Stage::fragment;
    case GL_COMPUTE_SHADER:
      return manifest::Stage::compute;
    default:
      return std::nullopt;
  }
}

std::string first_line(const std::string& log) {
  const size_t end = log.find('\n');
  return log.substr(0, end);
}

std::string program_log(GLuint program) {
  const ApplyGl& g = agl();
  char log[1024] = {};
  g.GetProgramInfoLog(program, sizeof log, nullptr, log);
  return log;
}

// Compiles one stage; returns 0 and the driver's message on failure.
GLuint compile(GLenum stage, const std::string& source, std::string* error) {
  const ApplyGl& g = agl();
  const GLuint shader = g.CreateShader(stage);
  if (!shader) {
    *error = "the driver made no shader object";
    return 0;
  }
  const GLchar* text = source.c_str();
  const GLint length = static_cast<GLint>(source.size());
  g.ShaderSource(shader, 1, &text, &length);
  g.CompileShader(shader);
  GLint ok = GL_FALSE;
  g.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == GL_TRUE) return shader;
  char log[1024] = {};
  g.GetShaderInfoLog(shader, sizeof log, nullptr, log);
  *error = first_line(log);
  g.DeleteShader(shader);
  return 0;
}

bool at_least(const GlCaps& caps, int major, int minor) {
  return caps.major > major || (caps.major == major && caps.minor >= minor);
}
bool has_program_interface(const GlCaps& caps) { return caps.gles ? at_least(caps, 3, 1) : at_least(caps, 4, 3); }

// What must be set before a variant links to behave as the app's program: the separable flag,
// attribute and fragment-output locations, transform-feedback varyings.
void copy_before_link(GLuint app, GLuint variant, const GlCaps& caps, const NameBindings& bindings) {
  const ApplyGl& g = agl();
  // What the app bound by name first (its program may lack some of those names), then the
  // locations its linked program actually has.
  for (const auto& [name, location] : bindings.attributes) g.BindAttribLocation(variant, location, name.c_str());
  if (g.BindFragDataLocationIndexed)
    for (const auto& [name, where] : bindings.frag_data)
      g.BindFragDataLocationIndexed(variant, where.first, where.second, name.c_str());
  if (g.ProgramParameteri && (caps.gles ? at_least(caps, 3, 1) : at_least(caps, 4, 1))) {
    GLint separable = GL_FALSE;
    g.GetProgramiv(app, GL_PROGRAM_SEPARABLE, &separable);
    if (separable) g.ProgramParameteri(variant, GL_PROGRAM_SEPARABLE, GL_TRUE);
  }
  char name[512];
  GLint count = 0;
  g.GetProgramiv(app, GL_ACTIVE_ATTRIBUTES, &count);
  for (GLint i = 0; i < count; ++i) {
    GLsizei length = 0;
    GLint size = 0;
    GLenum type = 0;
    g.GetActiveAttrib(app, static_cast<GLuint>(i), sizeof name, &length, &size, &type, name);
    if (length <= 0 || std::string_view(name).rfind("gl_", 0) == 0) continue;
    const GLint location = g.GetAttribLocation(app, name);
    if (location >= 0) g.BindAttribLocation(variant, static_cast<GLuint>(location), name);
  }
  if (!caps.gles && has_program_interface(caps) && g.GetProgramInterfaceiv && g.GetProgramResourceName &&
      g.BindFragDataLocationIndexed && g.GetFragDataLocation && g.GetFragDataIndex) {
    GLint outputs = 0;
    g.GetProgramInterfaceiv(app, GL_PROGRAM_OUTPUT, GL_ACTIVE_RESOURCES, &outputs);
    for (GLint i = 0; i < outputs; ++i) {
      GLsizei length = 0;
      g.GetProgramResourceName(app, GL_PROGRAM_OUTPUT, static_cast<GLuint>(i), sizeof name, &length, name);
      if (length <= 0 || std::string_view(name).rfind("gl_", 0) == 0) continue;
      const GLint location = g.GetFragDataLocation(app, name);
      const GLint index = g.GetFragDataIndex(app, name);
      if (location >= 0)
        g.BindFragDataLocationIndexed(variant, static_cast<GLuint>(location),
                                      static_cast<GLuint>(index < 0 ? 0 : index), name);
    }
  }
  GLint varyings = 0;
  g.GetProgramiv(app, GL_TRANSFORM_FEEDBACK_VARYINGS, &varyings);
  if (varyings > 0 && g.TransformFeedbackVaryings && g.GetTransformFeedbackVarying) {
    GLint mode = GL_INTERLEAVED_ATTRIBS;
    g.GetProgramiv(app, GL_TRANSFORM_FEEDBACK_BUFFER_MODE, &mode);
    std::vector<std::string> names;
    for (GLint i = 0; i < varyings; ++i) {
      GLsizei length = 0, size = 0;
      GLenum type = 0;
      g.GetTransformFeedbackVarying(app, static_cast<GLuint>(i), sizeof name, &length, &size, &type, name);
      names.emplace_back(name, static_cast<size_t>(length > 0 ? length : 0));
    }
    std::vector<const GLchar*> pointers;
    for (const std::string& n : names) pointers.push_back(n.c_str());
    g.TransformFeedbackVaryings(variant, varyings, pointers.data(), static_cast<GLenum>(mode));
  }
}

struct ActiveUniform {
  GLenum type = 0;
  GLint size = 0;
};

// Active default-block uniforms by base name ("u_light_color" for "u_light_color[0]").
std::map<std::string, ActiveUniform> active_uniforms(GLuint program) {
  const ApplyGl& g = agl();
  std::map<std::string, ActiveUniform> out;
  GLint count = 0;
  g.GetProgramiv(program, GL_ACTIVE_UNIFORMS, &count);
  char name[512];
  for (GLint i = 0; i < count; ++i) {
    GLsizei length = 0;
    GLint size = 0;
    GLenum type = 0;
    g.GetActiveUniform(program, static_cast<GLuint>(i), sizeof name, &length, &size, &type, name);
    if (length <= 0) continue;
    std::string base(name, static_cast<size_t>(length));
    if (base.size() > 3 && base.compare(base.size() - 3, 3, "[0]") == 0) base.resize(base.size() - 3);
    out[base] = {type, size};
  }
  return out;
}

std::string element_name(const std::string& base, GLint size, GLint element) {
  return size > 1 ? base + "[" + std::to_string(element) + "]" : base;
}

bool held_by_level(const manifest::Level& level, const std::string& base) {
  for (const auto& [name, value] : level.uniforms)
    if (name == base) return true;
  return false;
}

// The location table of one variant, with the app's current values copied in.
void map_uniforms(GLuint app, Variant& v, const manifest::Level& level) {
  const ApplyGl& g = agl();
  const auto app_uniforms = active_uniforms(app);
  const auto variant_uniforms = active_uniforms(v.program);
  for (const auto& [base, info] : app_uniforms) {
    auto it = variant_uniforms.find(base);
    const bool usable = it != variant_uniforms.end() && it->second.type == info.type && !held_by_level(level, base);
    for (GLint e = 0; e < info.size; ++e) {
      const std::string name = element_name(base, info.size, e);
      const GLint app_location = g.GetUniformLocation(app, name.c_str());
      if (app_location < 0) continue;  // a block member or a built-in
      GLint variant_location = -1;
      if (usable && e < it->second.size) variant_location = g.GetUniformLocation(v.program, name.c_str());
      if (static_cast<size_t>(app_location) >= v.location.size())
        v.location.resize(static_cast<size_t>(app_location) + 1, -1);
      v.location[static_cast<size_t>(app_location)] = variant_location;
      if (variant_location >= 0) copy_uniform(app, app_location, v.program, variant_location, info.type);
    }
  }
}

void hold_uniforms(const manifest::Pass& pass, size_t level_index, const manifest::Level& level, GLuint program) {
  const ApplyGl& g = agl();
  const auto uniforms = active_uniforms(program);
  for (const auto& [name, value] : level.uniforms) {
    auto it = uniforms.find(name);
    const std::string where = "pass '" + pass.name + "' level " + std::to_string(level_index);
    if (it == uniforms.end()) {
      say_once(where + name,
               "uniform '" + name + "' of " + where + " is not an active uniform of the program; not held");
      continue;
    }
    const GLint location = g.GetUniformLocation(program, (it->second.size > 1 ? name + "[0]" : name).c_str());
    if (location < 0 || !set_uniform(program, location, it->second.type, it->second.size, value.values))
      say_once(where + name, "uniform '" + name + "' of " + where + ": " + std::to_string(value.values.size()) +
                                 " values do not fill whole elements of its type; not held");
  }
}

void map_blocks(GLuint app, Variant& v, const GlCaps& caps) {
  const ApplyGl& g = agl();
  char name[512];
  GLint blocks = 0;
  g.GetProgramiv(app, GL_ACTIVE_UNIFORM_BLOCKS, &blocks);
  for (GLint i = 0; i < blocks; ++i) {
    GLsizei length = 0;
    g.GetActiveUniformBlockName(app, static_cast<GLuint>(i), sizeof name, &length, name);
    const GLuint index = g.GetUniformBlockIndex(v.program, name);
    v.uniform_block.push_back(index == GL_INVALID_INDEX ? -1 : static_cast<GLint>(index));
    if (index == GL_INVALID_INDEX) continue;
    GLint binding = 0;
    g.GetActiveUniformBlockiv(app, static_cast<GLuint>(i), GL_UNIFORM_BLOCK_BINDING, &binding);
    g.UniformBlockBinding(v.program, index, static_cast<GLuint>(binding));
  }
  if (!has_program_interface(caps) || !g.GetProgramInterfaceiv || !g.ShaderStorageBlockBinding) return;
  GLint storage = 0;
  g.GetProgramInterfaceiv(app, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &storage);
  for (GLint i = 0; i < storage; ++i) {
    GLsizei length = 0;
    g.GetProgramResourceName(app, GL_SHADER_STORAGE_BLOCK, static_cast<GLuint>(i), sizeof name, &length, name);
    const GLuint index = g.GetProgramResourceIndex(v.program, GL_SHADER_STORAGE_BLOCK, name);
    v.storage_block.push_back(index == GL_INVALID_INDEX ? -1 : static_cast<GLint>(index));
    if (index == GL_INVALID_INDEX) continue;
    const GLenum property = GL_BUFFER_BINDING;
    GLint binding = 0;
    g.GetProgramResourceiv(app, GL_SHADER_STORAGE_BLOCK, static_cast<GLuint>(i), 1, &property, 1, nullptr, &binding);
    g.ShaderStorageBlockBinding(v.program, index, static_cast<GLuint>(binding));
  }
}

// A program's subroutine interface of one stage (GL 4.0), with names to match another
// program's by. Only for stages the program has: the driver raises an error for the others.
struct StageInterface {
  SubroutineStage stage;
  std::vector<std::string> subroutine;     // by index ("": none)
  std::vector<std::string> location_name;  // by location ("": no uniform there; "u[1]" for arrays)
};

StageInterface stage_interface(GLuint program, GLenum stage) {
  const ApplyGl& g = agl();
  StageInterface out;
  GLint locations = 0, subroutines = 0, uniforms = 0;
  g.GetProgramStageiv(program, stage, GL_ACTIVE_SUBROUTINE_UNIFORM_LOCATIONS, &locations);
  g.GetProgramStageiv(program, stage, GL_ACTIVE_SUBROUTINES, &subroutines);
  g.GetProgramStageiv(program, stage, GL_ACTIVE_SUBROUTINE_UNIFORMS, &uniforms);
  out.stage.locations = locations > 0 ? locations : 0;
  out.stage.compatible.resize(static_cast<size_t>(out.stage.locations));
  out.location_name.resize(static_cast<size_t>(out.stage.locations));
  char name[512];
  for (GLint i = 0; i < subroutines; ++i) {
    GLsizei length = 0;
    g.GetActiveSubroutineName(program, stage, static_cast<GLuint>(i), sizeof name, &length, name);
    if (length <= 0) continue;
    const GLuint index = g.GetSubroutineIndex(program, stage, name);
    if (index == GL_INVALID_INDEX) continue;
    if (index >= out.subroutine.size()) out.subroutine.resize(index + 1);
    out.subroutine[index].assign(name, static_cast<size_t>(length));
  }
  out.stage.subroutines = static_cast<GLuint>(out.subroutine.size());
  for (GLint u = 0; u < uniforms; ++u) {
    GLsizei length = 0;
    g.GetActiveSubroutineUniformName(program, stage, static_cast<GLuint>(u), sizeof name, &length, name);
    if (length <= 0) continue;
    std::string base(name, static_cast<size_t>(length));
    if (base.size() > 3 && base.compare(base.size() - 3, 3, "[0]") == 0) base.resize(base.size() - 3);
    GLint size = 1, count = 0;
    g.GetActiveSubroutineUniformiv(program, stage, static_cast<GLuint>(u), GL_UNIFORM_SIZE, &size);
    g.GetActiveSubroutineUniformiv(program, stage, static_cast<GLuint>(u), GL_NUM_COMPATIBLE_SUBROUTINES, &count);
    std::vector<GLint> compatible(static_cast<size_t>(count > 0 ? count : 0));
    if (count > 0)
      g.GetActiveSubroutineUniformiv(program, stage, static_cast<GLuint>(u), GL_COMPATIBLE_SUBROUTINES,
                                     compatible.data());
    // An array's elements have consecutive locations.
    const GLint first = g.GetSubroutineUniformLocation(program, stage, base.c_str());
    for (GLint e = 0; first >= 0 && e < size; ++e) {
      const GLint location = first + e;
      if (location >= out.stage.locations) break;
      out.location_name[static_cast<size_t>(location)] = element_name(base, size, e);
      for (GLint c : compatible)
        if (c >= 0) out.stage.compatible[static_cast<size_t>(location)].push_back(static_cast<GLuint>(c));
    }
  }
  return out;
}

bool has_subroutines(const GlCaps& caps) {
  const ApplyGl& g = agl();
  return !caps.gles && at_least(caps, 4, 0) && g.GetProgramStageiv && g.GetActiveSubroutineName &&
         g.GetActiveSubroutineUniformName && g.GetActiveSubroutineUniformiv && g.GetSubroutineIndex &&
         g.GetSubroutineUniformLocation && g.UniformSubroutinesuiv;
}

// The stages a program was linked from, by slot (each once).
std::vector<std::pair<int, GLenum>> program_stages(const std::vector<ShaderSource>& sources) {
  std::vector<std::pair<int, GLenum>> out;
  for (const ShaderSource& s : sources) {
    const int slot = shader_stage_slot(s.stage);
    if (slot >= 0 && std::find_if(out.begin(), out.end(), [&](const auto& p) { return p.first == slot; }) == out.end())
      out.emplace_back(slot, s.stage);
  }
  return out;
}

// The variant's subroutine tables: the app's indices and locations matched by name.
void map_subroutines(const std::array<StageInterface, kShaderStages>& app,
                     const std::vector<std::pair<int, GLenum>>& stages, Variant& v) {
  for (const auto& [slot, stage] : stages) {
    const StageInterface& a = app[static_cast<size_t>(slot)];
    StageInterface own = stage_interface(v.program, stage);
    SubroutineMap& m = v.subroutines[static_cast<size_t>(slot)];
    std::map<std::string, GLuint> index_of;
    for (size_t i = 0; i < own.subroutine.size(); ++i)
      if (!own.subroutine[i].empty()) index_of[own.subroutine[i]] = static_cast<GLuint>(i);
    m.index.assign(a.subroutine.size(), GL_INVALID_INDEX);
    for (size_t i = 0; i < a.subroutine.size(); ++i) {
      auto it = a.subroutine[i].empty() ? index_of.end() : index_of.find(a.subroutine[i]);
      if (it != index_of.end()) m.index[i] = it->second;
    }
    std::map<std::string, GLint> app_location_of;
    for (size_t l = 0; l < a.location_name.size(); ++l)
      if (!a.location_name[l].empty()) app_location_of[a.location_name[l]] = static_cast<GLint>(l);
    m.app_location.assign(own.location_name.size(), -1);
    for (size_t l = 0; l < own.location_name.size(); ++l) {
      auto it = own.location_name[l].empty() ? app_location_of.end() : app_location_of.find(own.location_name[l]);
      if (it != app_location_of.end()) m.app_location[l] = it->second;
    }
    m.own = std::move(own.stage);
  }
}

// The sources of a level's variant: replaced stages, then the level's #defines in every stage.
std::vector<ShaderSource> variant_sources(const std::vector<ShaderSource>& app, const manifest::Level& level) {
  std::vector<ShaderSource> out;
  for (const ShaderSource& s : app) {
    ShaderSource v = s;
    if (auto stage = manifest_stage(s.stage)) {
      auto r = level.replace_source.find(*stage);
      if (r != level.replace_source.end()) v.source = r->second;
    }
    v.source = instrument::set_defines(v.source, level.defines);
    out.push_back(std::move(v));
  }
  return out;
}

// Set once the driver has run out of memory building a variant: none is built after it (each
// would ask for more of what is short); levels without one draw the app's programs.
std::atomic<bool> g_out_of_memory{false};

// GLBUDGET_TEST_OUT_OF_MEMORY=pass:level (a test switch): while that level's variant is built,
// ask the driver for a buffer no machine has, for a real GL_OUT_OF_MEMORY from the driver.
void provoke_out_of_memory_for_test(const std::string& pass, size_t level) {
  const auto& wanted = options().test_out_of_memory;
  if (std::find(wanted.begin(), wanted.end(), std::pair{pass, level}) == wanted.end()) return;
  const GlCalls& g = gl();
  if (!g.GenBuffers || !g.BindBuffer || !g.BufferData || !g.DeleteBuffers) return;
  GLint bound = 0;
  g.GetIntegerv(GL_COPY_WRITE_BUFFER_BINDING, &bound);
  GLuint buffer = 0;
  g.GenBuffers(1, &buffer);
  g.BindBuffer(GL_COPY_WRITE_BUFFER, buffer);
  g.BufferData(GL_COPY_WRITE_BUFFER, std::numeric_limits<GLsizeiptr>::max() / 2, nullptr, GL_STATIC_DRAW);
  g.BindBuffer(GL_COPY_WRITE_BUFFER, static_cast<GLuint>(bound));
  g.DeleteBuffers(1, &buffer);
}

std::string error_names(const std::vector<GLenum>& errors) {
  std::string names;
  for (GLenum e : errors) names += (names.empty() ? "" : ", ") + gl_error_name(e);
  return names;
}

GLuint link_sources(GLuint app, const std::vector<ShaderSource>& sources, const GlCaps& caps,
                    const NameBindings& bindings, std::string* error) {
  const ApplyGl& g = agl();
  std::vector<GLuint> shaders;
  bool ok = true;
  for (const ShaderSource& s : sources) {
    const GLuint shader = compile(s.stage, s.source, error);
    if (!shader) {
      ok = false;
      break;
    }
    shaders.push_back(shader);
  }
  GLuint program = 0;
  if (ok) {
    program = g.CreateProgram();
    for (GLuint s : shaders) g.AttachShader(program, s);
    copy_before_link(app, program, caps, bindings);
    g.LinkProgram(program);
    GLint linked = GL_FALSE;
    g.GetProgramiv(program, GL_LINK_STATUS, &linked);
    if (linked != GL_TRUE) {
      *error = "does not link: " + first_line(program_log(program));
      g.DeleteProgram(program);
      program = 0;
    } else {
      for (GLuint s : shaders) g.DetachShader(program, s);
    }
  } else {
    *error = "does not compile: " + *error;
  }
  for (GLuint s : shaders) g.DeleteShader(s);
  return program;
}

// Linked from instrumented sources when `inst` is given and the instrumented variant builds;
// else from `sources` as they are.
GLuint link_variant(GLuint app, const std::vector<ShaderSource>& sources, const GlCaps& caps,
                    const NameBindings& bindings, Instrumentation* inst, const std::string& variant_hash,
                    const std::string& where, bool* instrumented, std::string* error) {
  *instrumented = false;
  if (inst) {
    std::vector<std::pair<GLenum, std::string>> stages;
    for (const ShaderSource& s : sources) stages.emplace_back(s.stage, s.source);
    InstrumentedVariant iv = instrument_variant(*inst, stages, variant_hash);
    if (iv.any) {
      std::vector<ShaderSource> counted = sources;
      for (size_t i = 0; i < counted.size(); ++i) counted[i].source = iv.sources[i];
      std::string why;
      if (const GLuint program = link_sources(app, counted, caps, bindings, &why)) {
        after_variant_link(*inst, program, iv);
        *instrumented = true;
        return program;
      }
      say_once("variant-not-instrumented" + variant_hash,
               where + ": the instrumented variant " + why + "; it is built and drawn without counters");
    }
  }
  return link_sources(app, sources, caps, bindings, error);
}

}  // namespace

int shader_stage_slot(GLenum stage) {
  switch (stage) {
    case GL_VERTEX_SHADER:
      return 0;
    case GL_TESS_CONTROL_SHADER:
      return 1;
    case GL_TESS_EVALUATION_SHADER:
      return 2;
    case GL_GEOMETRY_SHADER:
      return 3;
    case GL_FRAGMENT_SHADER:
      return 4;
    case GL_COMPUTE_SHADER:
      return 5;
    default:
      return -1;
  }
}

int match_pass(PassId hash, const std::vector<ShaderSource>& sources) {
  const manifest::Manifest& m = active_manifest();
  std::vector<std::string> texts;
  for (const ShaderSource& s : sources) texts.push_back(s.source);
  for (size_t i = 0; i < m.passes.size(); ++i)
    if (!m.passes[i].match.empty() && manifest::matches(m.passes[i].match, hash, texts)) return static_cast<int>(i);
  return -1;
}

namespace {
// A level's sources with the fragment stage rewritten to see the app's pixels, when it reads
// any; `rewritten` says whether it did. Where a use cannot be followed, `refused` says which.
// A shader the rewrite cannot read is left to the driver, whose verdict the app gets anyway.
std::vector<ShaderSource> in_app_coordinates(const std::vector<ShaderSource>& sources, bool gles,
                                             const std::optional<std::vector<std::string>>& extensions,
                                             std::vector<instrument::AppSpaceSampler>* samplers, bool* frag_coord,
                                             bool* rewritten, std::string* refused) {
  *rewritten = false;
  std::vector<ShaderSource> out = sources;
  int needed = 0;
  for (ShaderSource& s : out) {
    if (s.stage != GL_FRAGMENT_SHADER) continue;
    // A GLSL ES shader may leave out #version (1.00); glslang would read it as desktop 1.10.
    std::string source = s.source;
    if (gles && source.find("#version") == std::string::npos) source = "#version 100\n#line 1\n" + source;
    instrument::AppSpaceResult r = instrument::to_app_space(source, extensions);
    if (!r.needed) continue;
    // Fragment shaders of one program would each declare the same helpers.
    if (++needed > 1) {
      if (refused->empty()) *refused = "more than one fragment shader object reads pixel coordinates";
      *rewritten = false;
      return sources;
    }
    if (!r.ok) {
      if (r.unsupported && refused->empty()) *refused = r.error;
      return sources;
    }
    s.source = std::move(r.source);
    *samplers = std::move(r.samplers);
    *frag_coord = r.frag_coord;
    *rewritten = true;
  }
  return *rewritten ? out : sources;
}

// The rewritten shader's own uniforms: located, and set to draw as the app's program does.
void locate_app_space(Variant& v, bool frag_coord, const std::vector<instrument::AppSpaceSampler>& samplers) {
  const ApplyGl& g = agl();
  if (frag_coord) v.app_space.frag_ratio = g.GetUniformLocation(v.program, instrument::kFragRatioUniform);
  if (v.app_space.frag_ratio >= 0) {
    const GLfloat one[2] = {1.0f, 1.0f};
    g.ProgramUniform2fv(v.program, v.app_space.frag_ratio, 1, one);
  }
  auto locate = [&](const std::string& name) {
    AppSpaceUniforms::Sampler s;
    s.sampler = g.GetUniformLocation(v.program, name.c_str());
    s.size = g.GetUniformLocation(v.program, (instrument::kSamplerSizePrefix + name).c_str());
    if (s.sampler >= 0 && s.size >= 0) v.app_space.samplers.push_back(s);  // else optimised away
    return s.sampler >= 0 || s.size >= 0;
  };
  for (const instrument::AppSpaceSampler& sampler : samplers) {
    if (!sampler.array) {
      locate(sampler.name);
      continue;
    }
    // Each element its own (an array's elements beyond the last one used are not active).
    for (int i = 0; i < 1024 && locate(sampler.name + "[" + std::to_string(i) + "]"); ++i) {
    }
  }
  v.app_space.given = std::make_shared<AppSpaceUniforms::Given>();
  v.app_space.given->sizes.assign(v.app_space.samplers.size(), {0, 0, 0});
}
}  // namespace

namespace {

// One program's variants, a level at a time: what every level shares (the app's program and
// sources, the subroutine interface read once) and how one level's program is built.
class VariantBuilder {
 public:
  VariantBuilder(GLuint program, PassId app_hash, int pass, const std::vector<ShaderSource>& sources,
                 const GlCaps& caps, const NameBindings& bindings, Instrumentation* inst, bool app_coordinates,
                 const std::optional<std::vector<std::string>>& driver_extensions, std::string* refused)
      : program_(program),
        app_hash_(app_hash),
        pass_(pass),
        manifest_pass_(pass >= 0 ? active_manifest().passes[static_cast<size_t>(pass)] : kNoPass),
        sources_(sources),
        caps_(caps),
        bindings_(bindings),
        inst_(inst),
        app_coordinates_(app_coordinates),
        driver_extensions_(driver_extensions),
        refused_(refused),
        // Subroutine uniforms (GL 4.0): the app's interface, read when the first variant links;
        // each variant's tables map from it.
        stages_(has_subroutines(caps) ? program_stages(sources) : std::vector<std::pair<int, GLenum>>{}) {}

  std::shared_ptr<VariantSet> build() {
    auto set = std::make_shared<VariantSet>();
    set->app_program = program_;
    set->pass = pass_;
    bool any = false;
    drain_gl_errors();  // raised by the shim's work before this (instrumenting the app's program): not a variant's
    for (size_t l = 0; l < manifest_pass_.levels.size(); ++l) {
      Variant v = level_variant(l, *set);
      any |= v.program != 0 || !v.draws;
      set->levels.push_back(std::move(v));
    }
    if (!any) return nullptr;
    if (app_stages_read_)
      for (const auto& [slot, stage] : stages_)
        set->app_subroutines[static_cast<size_t>(slot)] = app_stages_[static_cast<size_t>(slot)].stage;
    return set;
  }

 private:
  static inline const manifest::Pass kNoPass{.name = "", .match = {}, .levels = {manifest::Level{}}, .scales = {}};

  std::string where(size_t l) const {
    const manifest::Level& level = manifest_pass_.levels[l];
    return pass_ < 0 ? "program " + hash_text(app_hash_)
                     : "pass '" + manifest_pass_.name + "' level " + std::to_string(l) +
                           (level.name.empty() ? "" : " (" + level.name + ")");
  }

  // Level l's variant: the app's program where the level changes no shader and no rewrite is
  // needed, the shared app-coordinates twin where only the rewrite is, else a program of its own.
  Variant level_variant(size_t l, VariantSet& set) {
    const manifest::Level& level = manifest_pass_.levels[l];
    const bool changes = level.changes_program();
    if (!changes && app_twin_) {
      Variant v = *app_twin_;
      v.draws = level.draws;
      return v;
    }
    Variant v = app_variant(level);
    if (!(changes || app_coordinates_) || g_out_of_memory) return v;
    if (!apply_gl_has_program_uniforms()) {
      say_once("no-program-uniform", "variants need glProgramUniform* (GL 4.1, GLES 3.1); " + where(l) +
                                         " and every other program variant draw with the app's programs");
      return v;
    }
    const std::vector<ShaderSource> modified = changes ? variant_sources(sources_, level) : sources_;
    std::vector<uint64_t> hashes;
    for (const ShaderSource& s : modified) hashes.push_back(shader_hash(s.stage, s.source));
    // Its name in the log and the dump: the sources before the app-coordinates rewrite, which
    // only restores what the app drew.
    const PassId variant_hash = program_hash(std::move(hashes));
    std::vector<instrument::AppSpaceSampler> samplers;
    bool frag_coord = false, rewritten = false;
    const std::vector<ShaderSource> built =
        app_coordinates_
            ? in_app_coordinates(modified, caps_.gles, driver_extensions_, &samplers, &frag_coord, &rewritten, refused_)
            : modified;
    if (!changes && !rewritten) {
      app_twin_ = v;  // nothing to rewrite: the app's program as it is
      return v;
    }
    v = linked_variant(l, level, built, variant_hash, rewritten, frag_coord, samplers);
    if (v.program) set.programs.push_back(v.program);
    if (!changes) app_twin_ = v;  // built or not: the other identity levels share it
    return v;
  }

  Variant app_variant(const manifest::Level& level) const {
    Variant v;
    v.pass_hash = app_hash_;
    v.draws = level.draws;
    return v;
  }

  // Links `built` as level l's program with the app's interface carried over; the app's program
  // (an empty variant) where linking fails or raises a GL error, said once.
  Variant linked_variant(size_t l, const manifest::Level& level, const std::vector<ShaderSource>& built,
                         PassId variant_hash, bool rewritten, bool frag_coord,
                         const std::vector<instrument::AppSpaceSampler>& samplers) {
    const std::string at = where(l);
    Variant v = app_variant(level);
    v.dump_name = hash_text(variant_hash);
    if (variant_hash == app_hash_ && level.changes_program()) v.dump_name += "-level" + std::to_string(l);
    std::string error;
    v.program = link_variant(program_, built, caps_, bindings_, rewritten ? nullptr : inst_, v.dump_name, at,
                             &v.instrumented, &error);
    if (!v.program) {
      say_once(at + hash_text(app_hash_), at + ": the variant of program " + hash_text(app_hash_) + " " + error +
                                              "; this level draws the app's program");
    } else {
      v.pass_hash = variant_hash;
      map_uniforms(program_, v, level);
      map_blocks(program_, v, caps_);
      map_subroutines(app_stages(), stages_, v);
      if (pass_ >= 0) hold_uniforms(manifest_pass_, l, level, v.program);
      if (rewritten) locate_app_space(v, frag_coord, samplers);
    }
    // The app's errors were moved aside by the caller (OwnGlWork): what is pending now, the
    // variant's build raised. A variant built amid errors is not drawn.
    if (pass_ >= 0) provoke_out_of_memory_for_test(manifest_pass_.name, l);
    const std::vector<GLenum> raised = drain_gl_errors();
    if (raised.empty()) return v;
    if (v.program) agl().DeleteProgram(v.program);
    if (std::find(raised.begin(), raised.end(), GL_OUT_OF_MEMORY) != raised.end()) {
      g_out_of_memory = true;
      say(at + ": the driver ran out of memory (GL_OUT_OF_MEMORY) building the variant of program " +
          hash_text(app_hash_) + "; no more variants are built, and levels without one draw the app's programs");
    } else {
      say_once(at + hash_text(app_hash_) + "errors", at + ": building the variant of program " + hash_text(app_hash_) +
                                                         " raised " + error_names(raised) +
                                                         "; this level draws the app's program");
    }
    return app_variant(level);
  }

  // The app's subroutine interface per stage, read once (when the first variant links).
  const std::array<StageInterface, kShaderStages>& app_stages() {
    if (!app_stages_read_) {
      for (const auto& [slot, stage] : stages_)
        app_stages_[static_cast<size_t>(slot)] = stage_interface(program_, stage);
      app_stages_read_ = true;
    }
    return app_stages_;
  }

  GLuint program_;
  PassId app_hash_;
  int pass_;
  const manifest::Pass& manifest_pass_;
  const std::vector<ShaderSource>& sources_;
  const GlCaps& caps_;
  const NameBindings& bindings_;
  Instrumentation* inst_;
  bool app_coordinates_;
  const std::optional<std::vector<std::string>>& driver_extensions_;
  std::string* refused_;
  std::vector<std::pair<int, GLenum>> stages_;
  std::array<StageInterface, kShaderStages> app_stages_;
  bool app_stages_read_ = false;
  // The app's program in app coordinates, shared by the levels that otherwise draw it.
  std::optional<Variant> app_twin_;
};

}  // namespace

std::shared_ptr<VariantSet> build_variants(GLuint program, PassId app_hash, int pass,
                                           const std::vector<ShaderSource>& sources, const GlCaps& caps,
                                           const NameBindings& bindings, Instrumentation* inst, bool app_coordinates,
                                           const std::optional<std::vector<std::string>>& driver_extensions,
                                           std::string* refused) {
  return VariantBuilder(program, app_hash, pass, sources, caps, bindings, inst, app_coordinates, driver_extensions,
                        refused)
      .build();
}

void delete_variants(const VariantSet& set) {
  const ApplyGl& g = agl();
  for (GLuint p : set.programs) g.DeleteProgram(p);
}

void uniform_targets(const VariantSet& set, GLint app_location, UniformTargets* out) {
  out->count = 1;
  out->program[0] = set.app_program;
  out->location[0] = app_location;
  if (app_location < 0) return;
  const auto at = static_cast<size_t>(app_location);
  for (const Variant& v : set.levels) {
    if (!v.program || at >= v.location.size() || v.location[at] < 0 || out->count > kMaxPasses) continue;
    out->program[out->count] = v.program;
    out->location[out->count] = v.location[at];
    ++out->count;
  }
}

void forward_block_binding(const VariantSet& set, GLuint index, GLuint binding, bool storage) {
  const ApplyGl& g = agl();
  for (const Variant& v : set.levels) {
    if (!v.program) continue;
    const std::vector<GLint>& map = storage ? v.storage_block : v.uniform_block;
    if (index >= map.size() || map[index] < 0) continue;
    if (storage)
      g.ShaderStorageBlockBinding(v.program, static_cast<GLuint>(map[index]), binding);
    else
      g.UniformBlockBinding(v.program, static_cast<GLuint>(map[index]), binding);
  }
}

}  // namespace glbudget
