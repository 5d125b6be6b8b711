// ErrorFeedback (governor/loop/error_feedback.hpp): the ratio of the error probes measure of a
// configuration shown to its additive estimate, and the margin its spread asks for.
#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

#include "glbudget/loop/error_feedback.hpp"

using glbudget::loop::ErrorFeedback;
using glbudget::loop::ErrorFeedbackSettings;
using glbudget::model::Configuration;

namespace {
const Configuration kBest{0, 0, 0};
const Configuration kA{1, 0, 2};
const Configuration kB{0, 2, 0};
}  // namespace

TEST_CASE("error feedback: a configuration's ratio, the common one, and the margin of their spread",
          "[loop][error-feedback]") {
  ErrorFeedback feedback;
  const double floor = feedback.settings().floor;
  // Before any probe, estimates are left as they are.
  CHECK(feedback.correct(kA, 0.02) == 0.02);
  CHECK(feedback.correct(kB, 0.0) == 0.0);

  feedback.add(kA, 0.02, 0.03);
  CHECK(feedback.probes() == 1);
  CHECK(feedback.spread() == 0.0);
  // Its own measurement, exactly, for the configuration measured.
  CHECK(feedback.correct(kA, 0.02) == Approx(0.03).epsilon(1e-12));
  // The same ratio for one never shown, applied to its own estimate.
  CHECK(feedback.correct(kB, 0.01) == Approx((0.01 + floor) * (0.03 + floor) / (0.02 + floor) - floor));
  // The best configuration's error is 0 whatever the ratio.
  CHECK(feedback.correct(kBest, 0.0) == 0.0);

  // A second probe of kA off the first: the ratios move towards it and a margin opens.
  feedback.add(kA, 0.02, 0.02);
  // Measured at ratio 1 where the first said (0.03 + floor) / (0.02 + floor).
  const double first = std::log((0.03 + floor) / (0.02 + floor));
  CHECK(feedback.spread() == Approx(first));
  CHECK(feedback.log_ratio(kA) == Approx(0.5 * first));  // the mean of the two logs
  const double z = 1.6448536;                            // keep_share 0.95
  CHECK(feedback.correct(kA, 0.02) == Approx((0.02 + floor) * std::exp(0.5 * first + z * first) - floor));
}

TEST_CASE("error feedback: a ratio follows its last memory_probes probes", "[loop][error-feedback]") {
  ErrorFeedback feedback;
  for (int k = 0; k < 40; ++k) feedback.add(kA, 0.02, 0.04);
  for (int k = 0; k < 300; ++k) feedback.add(kA, 0.02, 0.01);
  const double floor = feedback.settings().floor;
  CHECK(feedback.log_ratio(kA) == Approx(std::log((0.01 + floor) / (0.02 + floor))).margin(1e-9));
  // The spread forgets the step too, over its last 32 probes: the deviations since are 0.
  CHECK(feedback.spread() < 0.005);
}

TEST_CASE("error feedback: what it ignores, and switched off", "[loop][error-feedback][extremes]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  ErrorFeedback feedback;
  feedback.add(kBest, 0.0, 0.01);  // the best's error is 0 by definition
  feedback.add(kA, nan, 0.01);
  feedback.add(kA, 0.01, nan);
  feedback.add(kA, inf, 0.01);
  feedback.add(kA, 0.01, -0.01);
  feedback.add(kA, -0.01, 0.01);
  CHECK(feedback.probes() == 0);
  CHECK(feedback.correct(kA, 0.02) == 0.02);

  // Both near 0: the floor keeps the ratio near 1 rather than dividing noise by noise.
  feedback.add(kA, 0.0, 0.0001);
  CHECK(feedback.probes() == 1);
  CHECK(feedback.correct(kB, 0.03) == Approx(0.03).epsilon(0.06));
  // A correction never makes an error negative, and a NaN estimate stays NaN.
  feedback.add(kA, 0.05, 0.0);
  CHECK(feedback.correct(kA, 0.0) >= 0.0);
  CHECK(std::isnan(feedback.correct(kA, nan)));

  ErrorFeedbackSettings off;
  off.enabled = false;
  ErrorFeedback disabled(off);
  disabled.add(kA, 0.02, 0.04);
  CHECK(disabled.probes() == 0);
  CHECK(disabled.correct(kA, 0.02) == 0.02);
  CHECK(disabled.log_ratio(kA) == 0.0);
}
