#pragma once
// The machine's pass-independent costs (PlatformCosts in platform_profile.hpp) as the prior a
// pass's coefficients start from. Their fit from recorded logs is offline analysis
// (glbudget/analysis/cost_fit.hpp).
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/power_model.hpp"

namespace glbudget::model {

// The coefficients a pass starts from at a level costing `level` (a pass outside any
// configuration space: a level of zero instructions and texels).
PassCoefficients prior_coefficients(const PlatformCosts& costs, const VariantCost& level);

// The costs' model for a frame: every pass drawn in it at its configuration's level.
PowerModel prior_model(const PlatformProfile& profile, const PlatformCosts& costs, const ConfigurationSpace& space,
                       const Configuration& configuration, const std::vector<PassFrame>& passes);

}  // namespace glbudget::model
