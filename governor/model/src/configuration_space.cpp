#include "glbudget/model/configuration_space.hpp"

#include <algorithm>

namespace glbudget::model {

ConfigurationSpace::ConfigurationSpace(std::vector<PassVariants> passes) : passes_(std::move(passes)) {
  strides_.resize(passes_.size());
  for (std::size_t i = passes_.size(); i-- > 0;) {
    if (passes_[i].levels.empty()) passes_[i].levels.push_back({});
    strides_[i] = size_;
    size_ *= passes_[i].levels.size();
  }
  scaled_by_.resize(passes_.size());
  scalers_of_.resize(passes_.size());
  for (std::size_t p = 0; p < passes_.size(); ++p) {
    for (std::size_t j = 0; j < passes_.size(); ++j) {
      if (std::find(passes_[p].scales.begin(), passes_[p].scales.end(), passes_[j].pass) == passes_[p].scales.end())
        continue;
      scaled_by_[p].push_back(j);
      scalers_of_[j].push_back(p);
    }
  }
}

std::size_t ConfigurationSpace::index_of(const Configuration& configuration) const {
  std::size_t index = 0;
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    index += static_cast<std::size_t>(configuration[i]) * strides_[i];
  }
  return index;
}

Configuration ConfigurationSpace::decode(std::size_t index) const {
  Configuration configuration(passes_.size());
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    configuration[i] = static_cast<int>(index / strides_[i]);
    index %= strides_[i];
  }
  return configuration;
}

Configuration ConfigurationSpace::cheapest() const {
  Configuration last_levels;
  for (const PassVariants& pass : passes_) last_levels.push_back(static_cast<int>(pass.levels.size()) - 1);
  return last_levels;
}

bool ConfigurationSpace::contains(const Configuration& configuration) const {
  if (configuration.size() != passes_.size()) return false;
  for (std::size_t i = 0; i < passes_.size(); ++i) {
    if (configuration[i] < 0 || static_cast<std::size_t>(configuration[i]) >= passes_[i].levels.size()) {
      return false;
    }
  }
  return true;
}

}  // namespace glbudget::model
