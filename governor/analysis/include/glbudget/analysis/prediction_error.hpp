#pragma once
// Prediction error as the issue reports it: mean absolute percentage error (MAPE) and mean
// absolute error as a share of the platform's power range P_M - P_m.
#include <cstddef>

namespace glbudget::analysis {

class PredictionError {
 public:
  explicit PredictionError(double range_w = 1.0) : range_w_(range_w) {}

  // Pairs with a NaN/infinite value are ignored; MAPE skips measurements <= 0 W.
  void add(double predicted_w, double measured_w);

  std::size_t count() const { return count_; }
  double mape_percent() const;         // NaN when empty
  double mean_share_of_range() const;  // NaN when empty or range <= 0
  double max_share_of_range() const;

 private:
  double range_w_;
  std::size_t count_ = 0;
  std::size_t percentage_count_ = 0;
  double percentage_sum_ = 0.0;
  double absolute_sum_ = 0.0;
  double absolute_max_ = 0.0;
};

}  // namespace glbudget::analysis
