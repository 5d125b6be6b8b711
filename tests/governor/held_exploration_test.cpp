#include <catch2/catch.hpp>

#include <limits>
#include <vector>

#include "glbudget/loop/held_exploration.hpp"

using glbudget::loop::explore_where_held;
using glbudget::loop::held_over_budget;
using glbudget::loop::HeldSelection;

namespace {

// Run Q's Sponza at 40 %, the selection of frame 122: the best, measured at 28.45 W; the
// configuration drawn, 2:0:1:1:1:0, measured (corrected prediction 20.14 W); one never
// measured predicted at 19.16 W and the cheapest at 22.12 W, each raised by the guard's 3 W.
// Budget 20.82 W, margin 6.97 W; the probes add 1.5 W to the windows; the range's low end, the
// calibrated cheapest, 15.73 W; the spread's margin 1.6 W. The cheapest then drew 16.7 W.
struct SponzaQ {
  std::vector<double> power = {28.45, 20.14, 19.16, 22.12};
  std::vector<double> weighed = {28.45, 20.14, 22.16, 25.12};
  std::vector<bool> measured = {true, true, false, false};
  HeldSelection held() const { return {1, weighed, power, &measured, 20.82, 6.97, 1.5}; }
};

}  // namespace

TEST_CASE("held over the budget at a measured configuration, the cheapest is drawn where the range says it draws less",
          "[loop][extremes]") {
  const SponzaQ q;
  CHECK(held_over_budget(q.held()));
  CHECK(explore_where_held(q.held(), 15.73, 1.6));
  // The range's low end not under the pick by more than the scatter: nothing to learn.
  CHECK_FALSE(explore_where_held(q.held(), 18.6, 1.6));
  CHECK(explore_where_held(q.held(), 18.5, 1.6));
  // A negative scatter counts as none.
  CHECK(explore_where_held(q.held(), 20.1, -5.0));
  CHECK_FALSE(explore_where_held(q.held(), 20.2, -5.0));
}

TEST_CASE("not held: something fits the margin, the pick was never measured, or its windows keep the budget",
          "[loop][extremes]") {
  SponzaQ q;
  // One configuration weighed within budget - margin (13.85 W): the selection took what fits.
  q.weighed[2] = 13.8;
  CHECK_FALSE(held_over_budget(q.held()));
  CHECK_FALSE(explore_where_held(q.held(), 15.73, 1.6));
  q.weighed[2] = 13.9;
  CHECK(held_over_budget(q.held()));

  // The pick never measured: the guard's own choice, whose first window is still to come.
  SponzaQ unmeasured;
  unmeasured.measured[1] = false;
  CHECK_FALSE(held_over_budget(unmeasured.held()));

  // The pick with its probes within the budget: its windows keep it.
  SponzaQ quiet;
  HeldSelection h = quiet.held();
  h.probes_w = 0.6;
  CHECK_FALSE(held_over_budget(h));
  h.probes_w = 0.7;
  CHECK(held_over_budget(h));
  h.probes_w = -3.0;  // counted as none
  CHECK_FALSE(held_over_budget(h));
}

TEST_CASE("held exploration: sizes that disagree and figures that are not finite", "[loop][extremes]") {
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  const SponzaQ q;
  HeldSelection h = q.held();
  h.pick = 4;
  CHECK_FALSE(held_over_budget(h));
  h = q.held();
  h.measured = nullptr;
  CHECK_FALSE(held_over_budget(h));
  const std::vector<bool> short_measured = {true, true};
  h = q.held();
  h.measured = &short_measured;
  CHECK_FALSE(held_over_budget(h));
  h = q.held();
  h.power_w = std::span<const double>(q.power).first(3);
  CHECK_FALSE(held_over_budget(h));
  for (const double bad : {kNaN, kInf}) {
    h = q.held();
    h.budget_w = bad;
    CHECK_FALSE(held_over_budget(h));
    h = q.held();
    h.margin_w = bad;
    CHECK_FALSE(held_over_budget(h));
    h = q.held();
    h.probes_w = bad;
    CHECK_FALSE(held_over_budget(h));
    CHECK_FALSE(explore_where_held(q.held(), bad, 1.6));
    CHECK_FALSE(explore_where_held(q.held(), 15.73, bad));
  }
  // No configurations at all.
  const std::vector<double> none;
  const std::vector<bool> none_measured;
  CHECK_FALSE(held_over_budget({0, none, none, &none_measured, 20.0, 1.0, 0.0}));
}
