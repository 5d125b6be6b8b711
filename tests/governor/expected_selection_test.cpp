#include <catch2/catch.hpp>

#include <cmath>
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

  // Something fits the margin under the guard: the selection stands.
  const std::vector<double> roomy = {20.5, 11.0, 12.24 + 3.4};
  const auto kept = select_configuration(roomy, error, 15.23, 3.56);
  CHECK(select_at_expected_power(kept, roomy, measured, error, 15.23, 3.56, 1.74).index == kept.index);

  // Lowered, an unmeasured one fits the margin: the lowest error among those that do.
  const std::vector<double> two = {20.5, 15.04, 13.0, 13.2};
  const std::vector<bool> two_measured = {true, true, false, false};
  const std::vector<double> two_error = {0.0, 0.011, 0.05, 0.03};
  const auto first = select_configuration(two, two_error, 15.23, 3.56);
  CHECK(select_at_expected_power(first, two, two_measured, two_error, 15.23, 3.56, 2.0).index == 3);

  // Nothing to lower, no margin, no budget, or sizes that do not agree: the selection stands.
  for (const double lowered :
       {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()})
    CHECK(select_at_expected_power(guarded, guarded_w, measured, error, 15.23, 3.56, lowered).index == 1);
  CHECK(select_at_expected_power(guarded, guarded_w, measured, error, 15.23, 0.0, 1.74).index == 1);
  CHECK(
      select_at_expected_power(guarded, guarded_w, measured, error, std::numeric_limits<double>::infinity(), 3.56, 1.74)
          .index == 1);
  CHECK(select_at_expected_power(guarded, guarded_w, {true, true}, error, 15.23, 3.56, 1.74).index == 1);
  // Every configuration measured: lowering changes nothing.
  CHECK(select_at_expected_power(guarded, guarded_w, {true, true, true}, error, 15.23, 3.56, 1.74).index == 1);
}
