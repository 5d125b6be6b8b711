#include "glbudget/model/online_fitter.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::model {
namespace {

std::vector<PassFrame> mean_counts(const std::vector<FrameSample>& window) {
  std::vector<PassCounts> sums;
  std::vector<bool> seen;
  for (const FrameSample& sample : window) {
    for (const PassFrame& pass : sample.passes) {
      if (sums.size() <= pass.pass) {
        sums.resize(static_cast<std::size_t>(pass.pass) + 1);
        seen.resize(sums.size(), false);
      }
      PassCounts& sum = sums[pass.pass];
      seen[pass.pass] = true;
      sum.batches += pass.counts.batches;
      sum.vertices += pass.counts.vertices;
      sum.fragments += pass.counts.fragments;
    }
  }
  std::vector<PassFrame> mean;
  const double n = static_cast<double>(std::max<std::size_t>(window.size(), 1));
  for (std::size_t pass = 0; pass < sums.size(); ++pass) {
    if (!seen[pass]) continue;
    const PassCounts& sum = sums[pass];
    mean.push_back({static_cast<PassIndex>(pass), {sum.batches / n, sum.vertices / n, sum.fragments / n}});
  }
  return mean;
}

}  // namespace

OnlineFitter::OnlineFitter(PlatformProfile profile, FitSettings settings)
    : settings_(settings), model_(profile), last_fit_{PowerModel(profile)} {
  settings_.fitting_window = std::max<std::size_t>(settings_.fitting_window, 1);
  settings_.check_window = std::max<std::size_t>(settings_.check_window, 1);
  window_.reserve(settings_.fitting_window);
}

OnlineFitter::Event OnlineFitter::add_frame(const FrameSample& sample, double predicted_power_w) {
  if (!is_usable(sample)) return Event::Rejected;
  if (phase_ == Phase::Fitting) {
    window_.push_back(sample);
    if (window_.size() < settings_.fitting_window) return Event::None;
    fit();
    return Event::Fitted;
  }
  if (!std::isfinite(predicted_power_w)) return Event::Rejected;
  check_error_sum_ += std::abs(predicted_power_w - sample.power_w);
  if (++check_frames_ < settings_.check_window) return Event::None;

  const double mean_error = check_error_sum_ / static_cast<double>(check_frames_);
  check_error_sum_ = 0.0;
  check_frames_ = 0;
  if (mean_error > settings_.refit_threshold * model_.profile().range_w()) {
    phase_ = Phase::Fitting;
    return Event::CheckFailed;
  }
  return Event::CheckPassed;
}

void OnlineFitter::configuration_changed() {
  window_.clear();
  check_error_sum_ = 0.0;
  check_frames_ = 0;
  // Before the first fit there is nothing to check against: keep collecting.
  phase_ = has_model() && !settings_.refit_on_change ? Phase::Checking : Phase::Fitting;
}

void OnlineFitter::fit() {
  last_fit_ = fit_window(window_, model_, settings_.regression);
  model_ = last_fit_.model;
  last_window_mean_ = mean_counts(window_);
  window_.clear();
  ++fits_;
  phase_ = Phase::Checking;
}

}  // namespace glbudget::model
