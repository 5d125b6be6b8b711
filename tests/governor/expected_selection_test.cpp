#include <catch2/catch.hpp>

#include <limits>
#include <vector>

#include "glbudget/loop/expected_selection.hpp"
#include "glbudget/model/selection.hpp"

using glbudget::loop::select_at_expected_power;
using glbudget::model::select_configuration;

TEST_CASE("where the guard leaves nothing within the margin, unmeasured configurations stand at their expected power",
          "[loop][extremes]") {
  // Run P's Valley at 40 %: the configuration drawn, measured at 15.04 W; a cheaper one never
  // measured, predicted at 12.24 W and guarded 3.4 W over it; the best, measured, far over.
  // Budget 15.23 W, margin 3.56 W, typical surprise 1.66 W (the guard less it: 1.74 W).
  const std::vector<double> guarded_w = {20.5, 15.04, 12.24 + 3.4};
  const std::vector<bool> measured = {true, true, false};
  const std::vector<double> error = {0.0, 0.011, 0.037};
  const glbudget::model::Selection guarded = select_configuration(guarded_w, error, 15.23, 3.56);
  CHECK(guarded.index == 1);  // the fallback at the guard's quantile: the one drawn, over in its windows
  const auto expected = select_at_expected_power(guarded, guarded_w, measured, error, 15.23, 3.56, 1.74);
  CHECK(expected.index == 2);  // at 13.9 W expected: the closest to keeping the margin
  CHECK(expected.budget_w == 15.23);

  // Lowered, unmeasured ones fit the margin: the lowest error among those that do.
  const std::vector<double> two = {20.5, 15.04, 15.5, 15.7};
  const std::vector<bool> two_measured = {true, true, false, false};
  const std::vector<double> two_error = {0.0, 0.011, 0.05, 0.03};
  const auto first = select_configuration(two, two_error, 15.23, 3.56);
  CHECK(first.index == 1);
  CHECK(select_at_expected_power(first, two, two_measured, two_error, 15.23, 3.56, 4.2).index == 3);
}

TEST_CASE("the expected power is not used where the guard leaves room, or picked one never measured",
          "[loop][extremes]") {
  // As in run P, but the unmeasured configuration has the lower error: lowered, it would be
  // chosen however the selection runs.
  const std::vector<double> error = {0.0, 0.02, 0.011};
  const std::vector<bool> measured = {true, true, false};
  // Something fits the margin under the guard: the selection stands.
  const std::vector<double> roomy = {20.5, 11.0, 12.24 + 3.4};
  const auto kept = select_configuration(roomy, error, 15.23, 3.56);
  REQUIRE(kept.index == 1);
  CHECK(select_at_expected_power(kept, roomy, measured, error, 15.23, 3.56, 1.74).index == 1);
  // No finite margin or budget: nothing to fall back from.
  const std::vector<double> tight = {20.5, 15.04, 12.24 + 3.4};
  const auto held = select_configuration(tight, error, 15.23, 3.56);
  REQUIRE(held.index == 1);
  REQUIRE(select_at_expected_power(held, tight, measured, error, 15.23, 3.56, 1.74).index == 2);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  CHECK(select_at_expected_power(held, tight, measured, error, 15.23, kInf, 1.74).index == 1);
  CHECK(select_at_expected_power(held, tight, measured, error, kInf, 3.56, 1.74).index == 1);
  CHECK(select_at_expected_power(held, tight, measured, error, 15.23, 3.56, kInf).index == 1);
  // Every configuration measured: nothing is lowered.
  CHECK(select_at_expected_power(held, tight, {true, true, true}, error, 15.23, 3.56, 1.74).index == 1);
  // The guard's own pick was never measured (the cheapest even at its quantile): it stands,
  // though lowering every unmeasured one alike would let a dearer one of lower error in.
  const std::vector<double> unmeasured_pick = {20.5, 16.0, 15.1, 15.3};
  const std::vector<bool> pick_measured = {true, true, false, false};
  const std::vector<double> pick_error = {0.0, 0.01, 0.03, 0.02};
  const auto cheapest = select_configuration(unmeasured_pick, pick_error, 15.23, 3.56);
  REQUIRE(cheapest.index == 2);
  CHECK(select_at_expected_power(cheapest, unmeasured_pick, pick_measured, pick_error, 15.23, 3.56, 4.0).index == 2);
}
