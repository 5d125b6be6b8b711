#pragma once
// The machine's pass-independent costs (model::PlatformCosts) fitted from recorded logs, for
// `glbudget costs` and `glbudget calibrate --app`.
//
// Calibration by regression over logs of any app that drew several configurations: every
// pass of every frame shares the five costs, through its own level's instructions and texels,
// so frames of different configurations and passes of different shaders tell them apart. Each
// log keeps a per-frame load of its own (an app's own work is no cost of the machine's).
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "glbudget/analysis/prediction_error.hpp"
#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/configured_sample.hpp"
#include "glbudget/model/platform_profile.hpp"

namespace glbudget::analysis {

struct CostLog {
  std::span<const model::ConfiguredSample> samples;
  const model::ConfigurationSpace* space = nullptr;
};

struct PlatformCostsFit {
  model::PlatformCosts costs;
  std::vector<double> frame_alpha;  // per log
  std::size_t samples_used = 0;
  // Per log, in sample: each frame, and each configuration's mean power.
  std::vector<PredictionError> per_frame, per_configuration;
};

// nullopt when no log has a usable frame in its space or the profile has no power range.
std::optional<PlatformCostsFit> fit_platform_costs(std::span<const CostLog> logs,
                                                   const model::PlatformProfile& profile);

}  // namespace glbudget::analysis
