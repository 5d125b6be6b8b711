#include "glbudget/loop/error_feedback.hpp"

#include <algorithm>
#include <cmath>

#include "normal_quantile.hpp"

namespace glbudget::loop {
namespace {

// The spread is the mean square of the last this-many deviations: at a probe every 10-60
// frames, the last minute or few of a run.
constexpr std::size_t kSpreadProbes = 32;

bool is_best(const model::Configuration& configuration) {
  return std::all_of(configuration.begin(), configuration.end(), [](int level) { return level == 0; });
}

}  // namespace

ErrorFeedback::ErrorFeedback(ErrorFeedbackSettings settings)
    : settings_(settings), z_(std::max(0.0, normal_quantile(settings.keep_share))) {}

void ErrorFeedback::add(const model::Configuration& shown, double estimated, double measured) {
  if (!settings_.enabled || !std::isfinite(estimated) || !std::isfinite(measured) || estimated < 0.0 ||
      measured < 0.0 || is_best(shown))
    return;
  const double floor = std::max(settings_.floor, 1e-9);
  const double log = std::log((measured + floor) / (estimated + floor));
  // How far the ratio this probe would have been corrected by was from what it measured.
  if (probes_ > 0) {
    const double deviation = log - log_ratio(shown);
    deviation_sq_ += (deviation * deviation - deviation_sq_) /
                     static_cast<double>(std::min<std::size_t>(++deviations_, kSpreadProbes));
  }
  const double memory = std::max(1.0, settings_.memory_probes);
  for (Ratio* ratio : {&ratios_[shown], &common_}) {
    ++ratio->probes;
    ratio->log += (log - ratio->log) / std::min(static_cast<double>(ratio->probes), memory);
  }
  ++probes_;
}

double ErrorFeedback::log_ratio(const model::Configuration& configuration) const {
  if (!settings_.enabled) return 0.0;
  const auto it = ratios_.find(configuration);
  return it != ratios_.end() ? it->second.log : common_.log;
}

double ErrorFeedback::spread() const { return deviations_ > 0 ? std::sqrt(deviation_sq_) : 0.0; }

double ErrorFeedback::correct(const model::Configuration& configuration, double estimated) const {
  if (!settings_.enabled || probes_ == 0 || !std::isfinite(estimated) || is_best(configuration)) return estimated;
  const double floor = std::max(settings_.floor, 1e-9);
  return std::max(0.0, (estimated + floor) * std::exp(log_ratio(configuration) + z_ * spread()) - floor);
}

void ErrorFeedback::correct_all(const model::ConfigurationSpace& space, std::vector<double>& error) const {
  if (!settings_.enabled || probes_ == 0) return;
  for (std::size_t i = 0; i < error.size() && i < space.size(); ++i) error[i] = correct(space.decode(i), error[i]);
}

}  // namespace glbudget::loop
