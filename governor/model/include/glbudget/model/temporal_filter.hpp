#pragma once
// Temporal filtering of paper §6.2: during a transition of length T from s_old to s_new the
// rendered configuration is s_eff = round((1 - t/T) s_old + (t/T) s_new), per pass.
#include "glbudget/model/configuration_space.hpp"

namespace glbudget::model {

// t is clamped to [0, T]; T <= 0 (or NaN t) switches at once. Halves round away from zero.
// Configurations of different lengths: s_new is returned.
Configuration blend_configurations(const Configuration& old_configuration, const Configuration& new_configuration,
                                   double t, double T);

}  // namespace glbudget::model
