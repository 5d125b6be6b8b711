#pragma once
// The machine's pass-independent costs (PlatformCosts in platform_profile.hpp): the prior a
// pass's coefficients start from, and their fit from recorded logs.
//
// Calibration by regression over logs of any app that drew several configurations: every
// pass of every frame shares the five costs, through its own level's instructions and texels,
// so frames of different configurations and passes of different shaders tell them apart. Each
// log keeps a per-frame load of its own (an app's own work is no cost of the machine's).
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/history_fit.hpp"
#include "glbudget/model/power_model.hpp"
#include "glbudget/model/prediction_error.hpp"

namespace glbudget::model {

// The coefficients a pass starts from at a level costing `level` (a pass outside any
// configuration space: a level of zero instructions and texels).
PassCoefficients prior_coefficients(const PlatformCosts& costs, const VariantCost& level);

// The costs' model for a frame: every pass drawn in it at its configuration's level.
PowerModel prior_model(const PlatformProfile& profile, const PlatformCosts& costs, const ConfigurationSpace& space,
                       const Configuration& configuration, const std::vector<PassFrame>& passes);

struct CostLog {
  std::span<const ConfiguredSample> samples;
  const ConfigurationSpace* space = nullptr;
};

struct PlatformCostsFit {
  PlatformCosts costs;
  std::vector<double> frame_alpha;  // per log
  std::size_t samples_used = 0;
  // Per log, in sample: each frame, and each configuration's mean power.
  std::vector<PredictionError> per_frame, per_configuration;
};

// nullopt when no log has a usable frame in its space or the profile has no power range.
std::optional<PlatformCostsFit> fit_platform_costs(std::span<const CostLog> logs, const PlatformProfile& profile);

}  // namespace glbudget::model
