// Before a draw with a program rewritten to see the app's pixels (instrument/app_space.hpp):
// its gl_FragCoord ratio for the framebuffer the draw goes to, and the app's sizes of the
// scaled textures its samplers read. Values already given are not given again.
#pragma once
#include <array>

#include "gl_types.hpp"
#include "variants.hpp"

namespace glbudget {

struct ContextState;

// glbudget_size_<sampler>: the app's width and height of level 0 and 1, or 0, 0, 0 when the
// texture is stored as the app made it.
using SamplerSize = std::array<GLint, 3>;

// The app's own draw with `set`'s program (bound, or its pipeline's fragment stage): the bound
// draw framebuffer's scale, the textures bound to the units.
void give_app_space_for_draw(ContextState& c, const VariantSet& set);
// A draw of a program whose shader could not be rewritten: said once, when it draws into a
// scaled target or while textures are scaled.
void report_app_space_refused(ContextState& c);

// `ratio`: app pixels per stored pixel of the target; `size_at_unit(unit)`: the SamplerSize of
// the texture at a unit. Used by quality probes, whose streams draw into their own shadows.
template <typename SizeAtUnit>
void give_app_space(const Variant& v, float ratio_x, float ratio_y, SizeAtUnit&& size_at_unit);

void give_frag_ratio(const Variant& v, float ratio_x, float ratio_y);
void give_sampler_size(const Variant& v, size_t sampler, const SamplerSize& size);
GLint sampler_unit(const Variant& v, size_t sampler);

template <typename SizeAtUnit>
void give_app_space(const Variant& v, float ratio_x, float ratio_y, SizeAtUnit&& size_at_unit) {
  give_frag_ratio(v, ratio_x, ratio_y);
  for (size_t i = 0; i < v.app_space.samplers.size(); ++i) give_sampler_size(v, i, size_at_unit(sampler_unit(v, i)));
}

}  // namespace glbudget
