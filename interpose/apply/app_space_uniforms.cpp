#include "app_space_uniforms.hpp"

#include <atomic>

#include "apply_gl.hpp"
#include "context_state.hpp"
#include "messages.hpp"
#include "pass_names.hpp"
#include "render_targets.hpp"

namespace glbudget {

void give_frag_ratio(const Variant& v, float ratio_x, float ratio_y) {
  if (v.app_space.frag_ratio < 0) return;
  std::array<float, 2>& given = v.app_space.given->ratio;
  if (given[0] == ratio_x && given[1] == ratio_y) return;
  given = {ratio_x, ratio_y};
  agl().ProgramUniform2fv(v.program, v.app_space.frag_ratio, 1, given.data());
}

GLint sampler_unit(const Variant& v, size_t sampler) {
  GLint unit = 0;
  agl().GetUniformiv(v.program, v.app_space.samplers[sampler].sampler, &unit);
  return unit;
}

void give_sampler_size(const Variant& v, size_t sampler, const SamplerSize& size) {
  SamplerSize& given = v.app_space.given->sizes[sampler];
  if (given == size) return;
  given = size;
  agl().ProgramUniform3iv(v.program, v.app_space.samplers[sampler].size, 1, given.data());
}

void give_app_space_for_draw(ContextState& c, const VariantSet& set) {
  const Variant& v = set.at(c.config);
  if (!v.program || !v.app_space.any()) return;
  TargetScaler& t = *c.targets;
  double sx = 1.0, sy = 1.0;
  t.stored_scale(t.app_draw_framebuffer(), &sx, &sy);
  const float ratio_x = static_cast<float>(1.0 / sx), ratio_y = static_cast<float>(1.0 / sy);
  if (!t.active()) {  // no app texture is stored at another size: no unit to ask about
    give_frag_ratio(v, ratio_x, ratio_y);
    for (size_t i = 0; i < v.app_space.samplers.size(); ++i) give_sampler_size(v, i, {0, 0, 0});
    return;
  }
  give_app_space(v, ratio_x, ratio_y, [&](GLint unit) -> SamplerSize {
    GLint w = 0, h = 0;
    bool scaled = false;
    if (!t.app_texture_size(t.texture_at_unit(unit), &w, &h, &scaled) || !scaled) return {0, 0, 0};
    return {w, h, 1};
  });
}

void report_app_space_refused(ContextState& c) {
  static std::atomic<bool> reported{false};
  if (reported.load(std::memory_order_relaxed)) return;
  TargetScaler& t = *c.targets;
  double sx = 1.0, sy = 1.0;
  t.stored_scale(t.app_draw_framebuffer(), &sx, &sy);
  if (sx == 1.0 && sy == 1.0 && !t.active()) return;
  std::string why;
  PassId pass = 0;
  {
    std::lock_guard lock(c.group->mu);
    auto it = c.group->programs.find(c.program);
    if (it == c.group->programs.end()) return;
    why = it->second.app_space_refused;
    pass = it->second.pass;
  }
  // Once per process: an engine may have many such programs.
  reported = true;
  say_once("app-space", "program " + hash_text(pass) +
                            " draws into scaled render targets in their pixel coordinates (" + why +
                            "): it may sample the wrong texels (other programs are not reported)");
}

}  // namespace glbudget
