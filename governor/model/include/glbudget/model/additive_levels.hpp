#pragma once
// A configuration's power as the best configuration's plus each pass's own change at its
// level, measured against the best alone: P(s) = P(s0) + sum_i [P(s_i^l_i) - P(s0)], s_i^l
// the best with pass i at level l. The same additivity over passes the error estimates use
// (paper §6.2), here for power; what a model predicts beyond it for a combination is how it
// makes the levels' changes interact.
//
// The governor uses it where `glbudget calibrate --app` measured each level alone and the
// cheapest configuration: the calibrated priors hold every single-level prediction to a
// measurement, and what is left of the run-time model in a combination is its interaction,
// fitted from the frames of the few configurations a run has drawn. On the demo's Hall that
// interaction swung the cheapest configuration's prediction between 14 and 31 W from one
// refit to the next (it measured 19 W): at 50 % the governor once found nothing predicted
// cheaper than a configuration with four passes at their best, and drew it over the budget.
// The calibrated cheapest says how far levels interact: the model's interaction is scaled to
// it (interaction_share), never amplified and never turned round.
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

// How much of a model's interaction to keep: the share of `interaction_w` (the model's
// prediction of the cheapest configuration less its levels' changes summed) that reaches
// `wanted_w` (the measured cheapest less the same sum), within [0, 1]. 0 where they differ in
// sign or either is 0 or not finite: the levels' changes summed.
double interaction_share(double interaction_w, double wanted_w);

}  // namespace glbudget::model
