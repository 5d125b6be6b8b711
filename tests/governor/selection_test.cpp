#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

#include "glbudget/model/selection.hpp"

using namespace glbudget::model;

TEST_CASE("budgets parse as share of range, watts or off", "[model][selection]") {
  CHECK(parse_budget("40%")->kind == Budget::Kind::ShareOfRange);
  CHECK(parse_budget("40%")->value == Approx(0.4));
  CHECK(parse_budget(" 0% ")->value == 0.0);
  CHECK(parse_budget("100%")->value == 1.0);
  CHECK(parse_budget("35W")->kind == Budget::Kind::Watts);
  CHECK(parse_budget("35.5w")->value == 35.5);
  CHECK(parse_budget("off")->kind == Budget::Kind::Off);
  CHECK(parse_budget("")->kind == Budget::Kind::Off);
  for (const char* bad : {"40", "abc%", "140%", "-3%", "-1W", "nan%", "inf W", "40%%"}) {
    CAPTURE(bad);
    CHECK(!parse_budget(bad));
  }
}

TEST_CASE("error budgets parse as 1 - SSIM in [0, 1]", "[model][selection]") {
  CHECK(parse_error_budget("0.02") == Approx(0.02));
  CHECK(parse_error_budget(" 0 ") == 0.0);
  CHECK(parse_error_budget("1") == 1.0);
  CHECK(parse_error_budget("1e-3") == Approx(0.001));
  for (const char* bad : {"", "x", "-0.01", "1.0001", "nan", "inf", "0.02%", "0.02 0.03", "1e400"}) {
    CAPTURE(bad);
    CHECK(!parse_error_budget(bad));
  }
}

TEST_CASE("selection takes the lowest error within the budget", "[model][selection]") {
  const std::vector<double> power{30, 40, 50, 60};
  const std::vector<double> error{0.30, 0.10, 0.05, 0.0};
  SECTION("40% of the scene's range") {
    const Selection s = select_configuration(power, error, *parse_budget("40%"));
    CHECK(s.budget_w == Approx(42.0));
    CHECK(s.index == 1);
    CHECK(s.within_budget);
  }
  SECTION("0% admits only the cheapest") {
    const Selection s = select_configuration(power, error, *parse_budget("0%"));
    CHECK(s.budget_w == 30.0);
    CHECK(s.index == 0);
    CHECK(s.within_budget);
  }
  SECTION("100% admits the most expensive") {
    CHECK(select_configuration(power, error, *parse_budget("100%")).index == 3);
  }
  SECTION("off") { CHECK(select_configuration(power, error, Budget{}).index == 3); }
  SECTION("watts") { CHECK(select_configuration(power, error, *parse_budget("50W")).index == 2); }
  SECTION("nothing fits: cheapest, flagged") {
    const Selection s = select_configuration(power, error, *parse_budget("10W"));
    CHECK(s.index == 0);
    CHECK(!s.within_budget);
  }
}

TEST_CASE("selection survives NaN, ties and a flat power range", "[model][selection][extremes]") {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<double> power{nan, 45, 40, 40};
  const std::vector<double> error{0.0, nan, 0.2, 0.2};
  const Selection s = select_configuration(power, error, *parse_budget("100%"));
  CHECK(s.index == 2);  // NaN power never admitted, NaN error ranks last, tie -> first lowest power
  // The top: the best-quality configuration whose power and error are known (40 W at 0.2).
  CHECK(s.budget_w == 40.0);
  CHECK(budget_watts(*parse_budget("100%"), power) == 45.0);  // without errors: the highest

  // P_M = P_m: every configuration predicts the same power, all are admitted at any share.
  const std::vector<double> flat(5, 20.0);
  const std::vector<double> errors{0.4, 0.3, 0.1, 0.2, 0.5};
  CHECK(select_configuration(flat, errors, *parse_budget("0%")).index == 2);
  CHECK(select_configuration(flat, errors, *parse_budget("0%")).within_budget);
}

TEST_CASE("a margin keeps the selection that far under the budget while anything is", "[selection][extremes]") {
  const std::vector<double> power{30.0, 25.0, 21.0, 15.0};
  const std::vector<double> error{0.0, 0.01, 0.02, 0.05};
  const Budget watts{Budget::Kind::Watts, 26.0};
  // No margin: 25 W fits 26 W. A 2-W margin: 25 W is too close, 21 W is taken.
  CHECK(select_configuration(power, error, watts).index == 1);
  const Selection margined = select_configuration(power, error, watts, 2.0);
  CHECK(margined.index == 2);
  CHECK(margined.budget_w == 26.0);
  CHECK(margined.within_budget);
  // A margin wider than the room under the budget: the cheapest, which comes closest to
  // keeping it, not the lowest error within the budget (25 W, at 26 W with a 2-W scatter).
  const Selection wide = select_configuration(power, error, Budget{Budget::Kind::Watts, 16.0}, 5.0);
  CHECK(wide.index == 3);
  CHECK(wide.within_budget);
  const Selection wider = select_configuration(power, error, watts, 12.0);
  CHECK(wider.index == 3);
  CHECK(wider.within_budget);
  const std::vector<double> tied{30.0, 25.0, 15.0, 15.0};  // of two cheapest, the lower error
  CHECK(select_configuration(tied, error, watts, 12.0).index == 2);
  // Nothing fits either way: the cheapest, said to be over.
  const Selection none = select_configuration(power, error, Budget{Budget::Kind::Watts, 10.0}, 1.0);
  CHECK(none.index == 3);
  CHECK_FALSE(none.within_budget);
  // NaN and infinite margins are no margin.
  CHECK(select_configuration(power, error, watts, std::nan("")).index == 1);
  CHECK(select_configuration(power, error, watts, std::numeric_limits<double>::infinity()).index == 1);
}

TEST_CASE("a share of the range runs up to the best-quality configuration's power", "[model][selection][extremes]") {
  // Configuration 2 (error 0.05) is predicted above the best one (3, error 0): a misprediction
  // that must not raise the budget.
  const std::vector<double> power{30, 40, 70, 60};
  const std::vector<double> error{0.30, 0.10, 0.05, 0.0};
  CHECK(budget_watts(*parse_budget("40%"), power) == Approx(46.0));  // the paper's: the highest
  const Selection s = select_configuration(power, error, *parse_budget("40%"));
  CHECK(s.budget_w == Approx(42.0));
  CHECK(s.index == 1);
  // 100 % admits the best configuration, and nothing predicted above it.
  const Selection all = select_configuration(power, error, *parse_budget("100%"));
  CHECK(all.budget_w == 60.0);
  CHECK(all.index == 3);
  // Ties at the least error: the highest of them is the top.
  CHECK(budget_watts(*parse_budget("100%"), std::vector<double>{30, 50, 45}, std::vector<double>{0.2, 0.0, 0.0}) ==
        50.0);
  // The best configuration's power unknown (NaN), or below every other: the highest, as before.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(budget_watts(*parse_budget("100%"), std::vector<double>{30, 50, nan}, std::vector<double>{0.2, 0.1, 0.0}) ==
        50.0);
  // An unknown error is no candidate for the top.
  CHECK(budget_watts(*parse_budget("50%"), std::vector<double>{30, 50}, std::vector<double>{0.2, nan}) == 30.0);
  CHECK(budget_watts(*parse_budget("50%"), std::vector<double>{30, 50}, std::vector<double>{nan, nan}) == 40.0);
  // Errors of another length than the powers are ignored.
  CHECK(budget_watts(*parse_budget("100%"), power, std::vector<double>{0.0}) == 70.0);
}
