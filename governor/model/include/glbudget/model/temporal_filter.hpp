#pragma once
// Temporal filtering of paper §6.2: during a transition of length T from s_old to s_new the
// rendered configuration is s_eff = round((1 - t/T) s_old + (t/T) s_new), per pass.
#include <functional>
#include <vector>

#include "glbudget/model/configuration_space.hpp"

namespace glbudget::model {

// t is clamped to [0, T]; T <= 0 (or NaN t) switches at once. Halves round away from zero.
// Configurations of different lengths: s_new is returned.
Configuration blend_configurations(const Configuration& old_configuration, const Configuration& new_configuration,
                                   double t, double T);

// Beyond the paper: the blend passes through configurations no selection weighed, and in the
// order of the passes' levels, not of their power: moving from 1:2:1:1:1:0 to 1:0:2:1:2:2 it
// drew 1:1:1:1:1:1, dearer than either end, for a second over a budget both ends kept (the
// demo's Sponza at 40 %). An ordered transition takes the blend's one-level steps at the
// blend's own moments (as many levels changed at each time as the blend changes), but in the
// order of their power: from `from`, each step moves one pass a level toward `to`, the one
// whose result power_w weighs lowest (not finite: after every finite one; ties: the lower
// pass), so that what a transition saves comes first and what it spends last.
struct TransitionPath {
  std::vector<Configuration> configurations;  // [0] `from`, back() `to`, one level apart
  std::vector<double> progress;               // t / T of each step, ascending (one fewer)
};
// Configurations of different lengths: the path is {to}, at once.
TransitionPath ordered_transition(const Configuration& from, const Configuration& to,
                                  const std::function<double(const Configuration&)>& power_w);

// The configuration `t` seconds into a transition of T along `path`: every step whose progress
// t / T has reached. t is clamped to [0, T]; T <= 0 (or NaN t): the path's end; an empty path:
// {}. The moments are exact; the blend's own arithmetic may round a t within a few ulps of one
// the other way.
Configuration along_path(const TransitionPath& path, double t, double T);

}  // namespace glbudget::model
