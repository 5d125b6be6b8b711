#pragma once
// The saturating curve of paper eq. (2), P = P_m + (P_M - P_m)(1 - exp(-alpha)), and its
// linearisation alpha = -ln(1 - (P - P_m)/(P_M - P_m)) used by the regression.
#include "glbudget/model/platform_profile.hpp"

namespace glbudget::model {

// Power for a load alpha. Uses expm1 so that tiny alphas keep full relative precision;
// alpha <= 0 (or NaN) gives P_m and alpha = +inf gives P_M.
double power_from_alpha(const PlatformProfile& profile, double alpha);

// The load alpha whose power is `power_w`, for use as a regression target. Measured power
// at or beyond P_M would need an infinite alpha, and below P_m a negative one, so the power
// fraction is clamped to [0, kMaxLoadFraction] before the log1p: its argument never reaches 0.
struct LinearisedPower {
  double alpha = 0.0;
  // exp(-alpha) = 1 - fraction: d(power)/d(alpha) divided by (P_M - P_m). Weighting a
  // regression row by it makes the alpha residual proportional to the power residual,
  // and makes clamped saturated samples nearly weightless.
  double weight = 1.0;
};
inline constexpr double kMaxLoadFraction = 0.999;
LinearisedPower linearise_power(const PlatformProfile& profile, double power_w);

}  // namespace glbudget::model
