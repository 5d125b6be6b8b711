#include "glbudget/model/temporal_filter.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::model {

Configuration blend_configurations(const Configuration& old_configuration, const Configuration& new_configuration,
                                   double t, double T) {
  if (old_configuration.size() != new_configuration.size() || !(T > 0.0) || std::isnan(t)) {
    return new_configuration;
  }
  const double progress = std::clamp(t / T, 0.0, 1.0);
  Configuration blended(new_configuration.size());
  for (std::size_t i = 0; i < blended.size(); ++i) {
    blended[i] =
        static_cast<int>(std::lround((1.0 - progress) * old_configuration[i] + progress * new_configuration[i]));
  }
  return blended;
}

}  // namespace glbudget::model
