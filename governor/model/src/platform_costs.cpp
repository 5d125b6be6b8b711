#include "glbudget/model/platform_costs.hpp"

#include "glbudget/model/reuse.hpp"

namespace glbudget::model {

PassCoefficients prior_coefficients(const PlatformCosts& costs, const VariantCost& level) {
  return {costs.batch, costs.vertex + costs.instruction * level.ins_v,
          costs.fragment + costs.instruction * level.ins_f + costs.texel * level.tex_f};
}

PowerModel prior_model(const PlatformProfile& profile, const PlatformCosts& costs, const ConfigurationSpace& space,
                       const Configuration& configuration, const std::vector<PassFrame>& passes) {
  PowerModel model(profile);
  const bool in_space = space.contains(configuration);
  for (const PassFrame& p : passes) {
    const VariantCost* level = in_space ? space.level_of(p.pass, configuration) : nullptr;
    // A skipped level draws nothing: a pass at it is costed as its cheapest drawing level.
    VariantCost cost = level ? *level : VariantCost{};
    if (level && !level->draws) cost = cheapest_drawing_level(space.passes()[p.pass]);
    model.set(p.pass, prior_coefficients(costs, cost));
  }
  return model;
}

}  // namespace glbudget::model
