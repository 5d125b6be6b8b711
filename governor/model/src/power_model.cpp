#include "glbudget/model/power_model.hpp"

#include <cmath>

#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {

bool is_usable(const FrameSample& sample) {
  if (!std::isfinite(sample.power_w)) return false;
  for (const PassFrame& pass : sample.passes) {
    for (double count : {pass.counts.batches, pass.counts.vertices, pass.counts.fragments}) {
      if (!std::isfinite(count) || count < 0.0) return false;
    }
  }
  return true;
}

double pass_alpha(const PlatformProfile& profile, const PassCoefficients& k, const PassCounts& c) {
  return k.k_b * (c.batches / profile.saturation_batches) + k.k_v * (c.vertices / profile.saturation_vertices) +
         k.k_f * (c.fragments / profile.saturation_fragments);
}

void PowerModel::set(PassIndex pass, const PassCoefficients& k) {
  if (coefficients_.size() <= pass) coefficients_.resize(static_cast<std::size_t>(pass) + 1);
  coefficients_[pass] = k;
}

std::size_t PowerModel::fitted_passes() const {
  std::size_t n = 0;
  for (const auto& k : coefficients_) n += k.has_value();
  return n;
}

double PowerModel::alpha(const std::vector<PassFrame>& passes) const {
  double sum = frame_alpha_;
  for (const PassFrame& pass : passes) {
    if (const PassCoefficients* k = find(pass.pass)) sum += pass_alpha(profile_, *k, pass.counts);
  }
  return sum;
}

double PowerModel::predict_power(const std::vector<PassFrame>& passes) const {
  return power_from_alpha(profile_, alpha(passes));
}

}  // namespace glbudget::model
