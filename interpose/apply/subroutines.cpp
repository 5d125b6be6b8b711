#include "subroutines.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "apply_gl.hpp"
#include "context_state.hpp"
#include "hooks_generated.hpp"

namespace glbudget {

namespace {

// By stage slot (shader_stage_slot).
const GLenum kStageOfSlot[kShaderStages] = {GL_VERTEX_SHADER,   GL_TESS_CONTROL_SHADER, GL_TESS_EVALUATION_SHADER,
                                            GL_GEOMETRY_SHADER, GL_FRAGMENT_SHADER,     GL_COMPUTE_SHADER};

thread_local std::vector<GLuint> t_indices;

// The level whose variant the driver has bound in place of the app's program; null when the
// driver has the app's own program.
const Variant* bound_variant(const ContextState& c) {
  const VariantSet* set = c.bound_variants.get();
  if (!set || c.real_program == set->app_program) return nullptr;
  for (const Variant& v : set->levels)
    if (v.program && v.program == c.real_program) return &v;
  return nullptr;
}

bool compatible_with(const std::vector<GLuint>& compatible, GLuint index) {
  return compatible.empty() || std::find(compatible.begin(), compatible.end(), index) != compatible.end();
}

// Whether the app's program would take `indices`: one compatible subroutine per location.
bool valid_selection(const SubroutineStage& app, GLsizei count, const GLuint* indices) {
  if (count != app.locations || (count > 0 && !indices)) return false;
  for (GLsizei l = 0; l < count; ++l)
    if (indices[l] >= app.subroutines || !compatible_with(app.compatible[static_cast<size_t>(l)], indices[l]))
      return false;
  return true;
}

// The app's selection in a variant's terms, through `select` (the driver's
// glUniformSubroutinesuiv): each of the variant's locations gets the subroutine of the same name
// as the app's choice for the uniform of the same name, else one compatible with it, so the
// call is always valid.
void select_in_variant(PFNGLUNIFORMSUBROUTINESUIVPROC select, GLenum stage, const SubroutineMap& m, const GLuint* app,
                       size_t app_count) {
  if (m.own.locations <= 0) return;  // nothing to select (and some drivers read past an empty table)
  t_indices.assign(static_cast<size_t>(m.own.locations), 0);
  for (size_t l = 0; l < t_indices.size(); ++l) {
    const std::vector<GLuint>& compatible = m.own.compatible[l];
    const GLint a = m.app_location[l];
    GLuint index = GL_INVALID_INDEX;
    if (a >= 0 && static_cast<size_t>(a) < app_count && app[a] < m.index.size()) index = m.index[app[a]];
    if (index == GL_INVALID_INDEX || !compatible_with(compatible, index))
      index = compatible.empty() ? 0 : compatible.front();
    t_indices[l] = index;
  }
  select(stage, m.own.locations, t_indices.data());
}

}  // namespace

void handle_glUniformSubroutinesuiv(pfn_glUniformSubroutinesuiv real, GLenum shadertype, GLsizei count,
                                    const GLuint* indices) {
  ContextState* c = current_context();
  if (!c || !c->bound_variants) return real(shadertype, count, indices);
  const int slot = shader_stage_slot(shadertype);
  if (slot < 0 || c->bound_variants->app_subroutines[static_cast<size_t>(slot)].locations < 0)
    return real(shadertype, count, indices);
  const SubroutineStage& app = c->bound_variants->app_subroutines[static_cast<size_t>(slot)];
  const bool valid = valid_selection(app, count, indices);
  if (valid) {
    SubroutineSelection& s = c->subroutines[static_cast<size_t>(slot)];
    s.set = c->bound_variants;
    s.indices.assign(indices, indices + count);
  }
  const Variant* v = bound_variant(*c);
  if (!v || v->subroutines[static_cast<size_t>(slot)].own.locations < 0) return real(shadertype, count, indices);
  // The app's program would refuse the call: so does the variant, with GL_INVALID_VALUE (a
  // negative count), and nothing changes.
  if (!valid) return real(shadertype, -1, indices);
  select_in_variant(real, shadertype, v->subroutines[static_cast<size_t>(slot)], indices, static_cast<size_t>(count));
}

void handle_glGetUniformSubroutineuiv(pfn_glGetUniformSubroutineuiv real, GLenum shadertype, GLint location,
                                      GLuint* params) {
  ContextState* c = current_context();
  const Variant* v = c && c->bound_variants ? bound_variant(*c) : nullptr;
  const int slot = shader_stage_slot(shadertype);
  if (!v || slot < 0) return real(shadertype, location, params);
  const SubroutineStage& app = c->bound_variants->app_subroutines[static_cast<size_t>(slot)];
  const SubroutineSelection& s = c->subroutines[static_cast<size_t>(slot)];
  if (app.locations < 0 || s.set != c->bound_variants) return real(shadertype, location, params);
  // A location the app's program lacks: the driver's GL_INVALID_VALUE, as the app would get.
  if (location < 0 || location >= app.locations)
    return real(shadertype, location < 0 ? location : std::numeric_limits<GLint>::max(), params);
  if (params) *params = s.indices[static_cast<size_t>(location)];
}

void reapply_subroutines(ContextState& c) {
  const std::shared_ptr<const VariantSet>& set = c.bound_variants;
  const Variant* v = set ? bound_variant(c) : nullptr;
  const ApplyGl& g = agl();
  for (int slot = 0; slot < kShaderStages; ++slot) {
    SubroutineSelection& s = c.subroutines[static_cast<size_t>(slot)];
    if (s.set && s.set != set) s = {};  // another program's, or made before a relink
    if (!set || !g.UniformSubroutinesuiv) continue;
    const SubroutineStage& app = set->app_subroutines[static_cast<size_t>(slot)];
    if (app.locations <= 0) continue;
    if (!s.set) {
      if (!v) continue;  // the app's own program keeps the driver's defaults, as without glbudget
      s.set = set;
      s.indices.resize(static_cast<size_t>(app.locations));
      for (size_t l = 0; l < s.indices.size(); ++l)
        s.indices[l] = app.compatible[l].empty() ? 0 : app.compatible[l].front();
    }
    const GLenum stage = kStageOfSlot[slot];
    if (!v) {
      g.UniformSubroutinesuiv(stage, app.locations, s.indices.data());
    } else if (v->subroutines[static_cast<size_t>(slot)].own.locations >= 0) {
      select_in_variant(g.UniformSubroutinesuiv, stage, v->subroutines[static_cast<size_t>(slot)], s.indices.data(),
                        s.indices.size());
    }
  }
}

}  // namespace glbudget
