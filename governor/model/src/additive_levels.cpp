#include "glbudget/model/additive_levels.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::model {

std::vector<std::vector<std::size_t>> single_level_indices(const ConfigurationSpace& space) {
  std::vector<std::vector<std::size_t>> indices(space.pass_count());
  Configuration single(space.pass_count(), 0);
  for (std::size_t i = 0; i < space.pass_count(); ++i) {
    const std::size_t levels = space.passes()[i].levels.size();
    for (std::size_t l = 0; l < levels; ++l) {
      single[i] = static_cast<int>(l);
      indices[i].push_back(space.index_of(single));
    }
    single[i] = 0;
  }
  return indices;
}

void make_additive_over_levels(const ConfigurationSpace& space, std::vector<double>& power) {
  if (power.size() != space.size() || space.size() < 2) return;
  const std::vector<std::vector<std::size_t>> single = single_level_indices(space);
  // Each pass's change at each level, read before any entry is overwritten.
  const double best = power[space.index_of(Configuration(space.pass_count(), 0))];
  std::vector<std::vector<double>> change(space.pass_count());
  for (std::size_t i = 0; i < single.size(); ++i)
    for (std::size_t index : single[i]) change[i].push_back(power[index] - best);
  // Row-major, last pass fastest: an odometer over the levels.
  Configuration levels(space.pass_count(), 0);
  for (std::size_t index = 0; index < power.size(); ++index) {
    double sum = best;
    for (std::size_t i = 0; i < levels.size(); ++i) sum += change[i][static_cast<std::size_t>(levels[i])];
    power[index] = sum;
    for (std::size_t i = levels.size(); i-- > 0;) {
      if (static_cast<std::size_t>(++levels[i]) < change[i].size()) break;
      levels[i] = 0;
    }
  }
}

double interaction_share(double interaction_w, double wanted_w) {
  if (!std::isfinite(interaction_w) || !std::isfinite(wanted_w) || interaction_w == 0.0) return 0.0;
  return std::clamp(wanted_w / interaction_w, 0.0, 1.0);
}

}  // namespace glbudget::model
