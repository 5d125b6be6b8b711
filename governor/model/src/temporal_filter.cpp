#include "glbudget/model/temporal_filter.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

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

TransitionPath ordered_transition(const Configuration& from, const Configuration& to,
                                  const std::function<double(const Configuration&)>& power_w) {
  if (from.size() != to.size()) return {{to}, {}};
  TransitionPath path{{from}, {}};
  // The blend moves a pass d levels at t / T = (j - 1/2) / d, j = 1..d: from that moment on a
  // pass whose level rises, just after it one whose level falls (lround rounds halves away
  // from zero).
  for (std::size_t i = 0; i < from.size(); ++i) {
    const int d = std::abs(to[i] - from[i]);
    for (int j = 1; j <= d; ++j) {
      const double at = (j - 0.5) / d;
      path.progress.push_back(to[i] > from[i] ? at : std::nextafter(at, 2.0));
    }
  }
  std::sort(path.progress.begin(), path.progress.end());
  Configuration at = from;
  while (at != to) {
    Configuration next;
    double next_w = 0.0;
    bool next_finite = false;
    for (std::size_t i = 0; i < at.size(); ++i) {
      if (at[i] == to[i]) continue;
      Configuration step = at;
      step[i] += to[i] > at[i] ? 1 : -1;
      const double w = power_w ? power_w(step) : std::numeric_limits<double>::quiet_NaN();
      const bool finite = std::isfinite(w);
      // The first candidate, else one finite where the best so far is not, else a lower weight.
      if (next.empty() || (finite && (!next_finite || w < next_w))) {
        next = std::move(step);
        next_w = w;
        next_finite = finite;
      }
    }
    at = next;
    path.configurations.push_back(at);
  }
  return path;
}

Configuration along_path(const TransitionPath& path, double t, double T) {
  if (path.configurations.empty()) return {};
  if (!(T > 0.0) || std::isnan(t)) return path.configurations.back();
  const double progress = std::clamp(t / T, 0.0, 1.0);
  const auto taken = static_cast<std::size_t>(std::upper_bound(path.progress.begin(), path.progress.end(), progress) -
                                              path.progress.begin());
  return path.configurations[std::min(taken, path.configurations.size() - 1)];
}

}  // namespace glbudget::model
