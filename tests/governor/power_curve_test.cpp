#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "glbudget/model/power_curve.hpp"

using namespace glbudget::model;

namespace {
PlatformProfile profile_20_60() {
  PlatformProfile p;
  p.p_min_w = 20.0;
  p.p_max_w = 60.0;
  return p;
}
}  // namespace

TEST_CASE("power curve keeps full precision as alpha goes to zero", "[model][extremes]") {
  // With P_m = 0 nothing absorbs the small term, so 1 - exp(-alpha) computed naively would
  // cancel to 0 (or to a handful of bits); expm1/log1p keep every digit.
  PlatformProfile zero_floor;
  zero_floor.p_min_w = 0.0;
  zero_floor.p_max_w = 40.0;
  for (double alpha : {1e-3, 1e-9, 1e-17, 1e-300}) {
    const double power = power_from_alpha(zero_floor, alpha);
    CHECK(
        power ==
        Approx(40.0 * alpha * (1.0 - alpha / 2.0 + alpha * alpha / 6.0 - alpha * alpha * alpha / 24.0)).epsilon(1e-12));
    CHECK(linearise_power(zero_floor, power).alpha == Approx(alpha).epsilon(1e-12));
  }
  const PlatformProfile p = profile_20_60();
  CHECK(power_from_alpha(p, 1e-300) == 20.0);  // rounds to P_m, never below
  CHECK(power_from_alpha(p, 0.0) == 20.0);
  CHECK(power_from_alpha(p, -5.0) == 20.0);
  CHECK(power_from_alpha(p, std::nan("")) == 20.0);
}

TEST_CASE("power curve saturates at P_M for very large alpha", "[model][extremes]") {
  const PlatformProfile p = profile_20_60();
  CHECK(power_from_alpha(p, 40.0) == Approx(60.0));
  CHECK(power_from_alpha(p, 1e300) == 60.0);
  CHECK(power_from_alpha(p, std::numeric_limits<double>::infinity()) == 60.0);
  CHECK(power_from_alpha(p, 5.0) < 60.0);
}

TEST_CASE("linearisation never takes the log of zero or less", "[model][extremes]") {
  const PlatformProfile p = profile_20_60();
  for (double power : {60.0, 60.0000001, 75.0, 1e12}) {
    const LinearisedPower l = linearise_power(p, power);
    CHECK(std::isfinite(l.alpha));
    CHECK(l.alpha == Approx(-std::log1p(-kMaxLoadFraction)));
    CHECK(l.weight == Approx(1.0 - kMaxLoadFraction));
  }
  for (double power : {20.0, 19.999, 0.0, -3.0}) {
    const LinearisedPower l = linearise_power(p, power);
    CHECK(l.alpha == 0.0);
    CHECK(l.weight == 1.0);
  }
  const LinearisedPower middle = linearise_power(p, 40.0);
  CHECK(middle.alpha == Approx(std::log(2.0)));
  CHECK(middle.weight == Approx(0.5));
}

TEST_CASE("linearisation gives nothing to learn from NaN, infinity or a zero range", "[model][extremes]") {
  const PlatformProfile p = profile_20_60();
  for (double power : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    CHECK(linearise_power(p, power).weight == 0.0);
    CHECK(linearise_power(p, power).alpha == 0.0);
  }
  PlatformProfile flat = p;
  flat.p_max_w = flat.p_min_w;
  CHECK(linearise_power(flat, 25.0).weight == 0.0);
  CHECK(power_from_alpha(flat, 3.0) == 20.0);  // P_M = P_m: every load costs P_m
}
