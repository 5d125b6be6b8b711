#include "glbudget/loop/scale_factors.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::loop {

ScaleFactors::ScaleFactors(double memory_probes, double prior_probes)
    : memory_probes_(std::max(1.0, memory_probes)), prior_probes_(std::max(0.0, prior_probes)) {}

void ScaleFactors::add(int scale_level, double scale_error, double others_error, double measured) {
  if (scale_level <= 0 || !std::isfinite(scale_error) || !std::isfinite(others_error) || !std::isfinite(measured) ||
      scale_error < 0.0 || others_error <= 0.0 || measured < 0.0)
    return;
  const auto level = static_cast<std::size_t>(scale_level);
  if (levels_.size() <= level) levels_.resize(level + 1);
  Sums& sums = levels_[level];
  const double keep = 1.0 - 1.0 / memory_probes_;
  sums.product = keep * sums.product + (measured - scale_error) * others_error;
  sums.square = keep * sums.square + others_error * others_error;
  sums.weight = keep * sums.weight + 1.0;
  ++probes_;
}

std::vector<double> ScaleFactors::factors(std::size_t levels) const {
  std::vector<double> m(levels, 1.0);
  for (std::size_t l = 1; l < levels && l < levels_.size(); ++l) {
    const Sums& sums = levels_[l];
    if (!(sums.square > 0.0)) continue;
    const double fitted = std::clamp(sums.product / sums.square, 0.5, 1.5);
    m[l] = 1.0 + (fitted - 1.0) * sums.weight / (sums.weight + prior_probes_);
  }
  return m;
}

}  // namespace glbudget::loop
