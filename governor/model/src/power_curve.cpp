#include "glbudget/model/power_curve.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::model {

double power_from_alpha(const PlatformProfile& profile, double alpha) {
  if (!(alpha > 0.0)) return profile.p_min_w;  // also catches NaN
  return profile.p_min_w + profile.range_w() * -std::expm1(-alpha);
}

LinearisedPower linearise_power(const PlatformProfile& profile, double power_w) {
  const double range = profile.range_w();
  if (!(range > 0.0) || !std::isfinite(power_w)) return {0.0, 0.0};  // nothing to learn
  const double fraction = std::clamp((power_w - profile.p_min_w) / range, 0.0, kMaxLoadFraction);
  return {-std::log1p(-fraction), 1.0 - fraction};
}

}  // namespace glbudget::model
