#pragma once
// A configuration's power as the best configuration's plus each pass's own change at its
// level, measured against the best alone: P(s) = P(s0) + sum_i [P(s_i^l_i) - P(s0)], s_i^l
// the best with pass i at level l. The same additivity over passes the error estimates use
// (paper §6.2), here for power.
//
// The governor predicts so where `glbudget calibrate --app` measured each level alone: the
// calibrated priors then hold every single-level prediction to a measurement, and what is
// left of the run-time model in a combination of levels is how it makes their savings
// interact, which it fits from the frames of the few configurations a run has drawn and
// cannot tell apart. On the demo's Hall, after one refit on frames of one configuration, the
// model made 2:2:2:2:2:2 cost 5 W more than the sum of its levels' changes, and more than a
// configuration with four passes at their best (it measured 19 W, predicted 30 W), so the
// governor, keeping a wide margin, found nothing cheaper to draw.
#include <cstddef>
#include <vector>

#include "glbudget/model/configuration_space.hpp"

namespace glbudget::model {

// The indices of the single-level configurations: [pass][level] -> index_of(s_pass^level)
// ([pass][0] is the best's, 0).
std::vector<std::vector<std::size_t>> single_level_indices(const ConfigurationSpace& space);

// power[index] for every configuration of `space`, replaced in place by the sum above over
// the values of the best and the single-level configurations. A NaN among those gives NaN
// where it is used.
void make_additive_over_levels(const ConfigurationSpace& space, std::vector<double>& power);

// The same sum for one configuration, `at(c)` giving any configuration's power.
template <class PowerOf>
double additive_over_levels(const Configuration& configuration, PowerOf&& at) {
  Configuration single(configuration.size(), 0);
  const double best = at(single);
  double sum = best;
  for (std::size_t i = 0; i < configuration.size(); ++i) {
    if (configuration[i] == 0) continue;
    single[i] = configuration[i];
    sum += at(single) - best;
    single[i] = 0;
  }
  return sum;
}

}  // namespace glbudget::model
