#include "glbudget/analysis/prediction_error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace glbudget::analysis {

using namespace glbudget::model;

void PredictionError::add(double predicted_w, double measured_w) {
  if (!std::isfinite(predicted_w) || !std::isfinite(measured_w)) return;
  const double absolute = std::abs(predicted_w - measured_w);
  ++count_;
  absolute_sum_ += absolute;
  absolute_max_ = std::max(absolute_max_, absolute);
  if (measured_w > 0.0) {
    ++percentage_count_;
    percentage_sum_ += absolute / measured_w;
  }
}

double PredictionError::mape_percent() const {
  if (percentage_count_ == 0) return std::numeric_limits<double>::quiet_NaN();
  return 100.0 * percentage_sum_ / static_cast<double>(percentage_count_);
}

double PredictionError::mean_share_of_range() const {
  if (count_ == 0 || !(range_w_ > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return absolute_sum_ / static_cast<double>(count_) / range_w_;
}

double PredictionError::max_share_of_range() const {
  if (count_ == 0 || !(range_w_ > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  return absolute_max_ / range_w_;
}

}  // namespace glbudget::analysis
