#pragma once
// Beyond the paper: the feedback's correction is fitted over the configurations measured, and
// where they drew more than predicted it raises the unmeasured ones that share their levels;
// the guard raises every unmeasured one further (power_feedback.hpp). On the demo's Sponza at
// 40 % (run Q, 2026-11-29) that put every configuration cheaper than the one drawn above it:
// nothing fitted the margin, and even at their expected power (expected_selection.hpp) the
// measured configuration came closest, so the selection held it, its windows with a probe over
// the budget, for 31 s (30 of 33 windows over). The cheapest was then predicted at 22.1 W, the
// range's low end (the calibrated cheapest) said 15.7 W, and it drew 16.7 W. Held over the
// budget at a measured configuration, a run learns of a cheaper one only by drawing it: where
// the range's low end says the cheapest draws less than the configuration held, beyond the
// sensor's scatter, the governor draws the cheapest for one window (Governor::explore_held,
// once per run). Even where the cheapest too would be over the budget with its probes, it is
// the closest the run can come; its window anchors the range's low end and teaches the
// correction what the levels save.
#include <cstddef>
#include <span>
#include <vector>

namespace glbudget::loop {

struct HeldSelection {
  std::size_t pick = 0;                         // the selection's configuration (space index)
  std::span<const double> weighed_w;            // every configuration's power as the selection weighed it
  std::span<const double> power_w;              // and its corrected prediction
  const std::vector<bool>* measured = nullptr;  // whether each was measured in the run
  double budget_w = 0.0;
  double margin_w = 0.0;  // what the selection kept under the budget
  // What the probes add to the pick's windows, as the selection's margin holds them
  // (ProbeOverhead::window_margin_w: a probe's whole excess where most windows hold one).
  double probes_w = 0.0;
};

// Whether the selection holds a measured configuration over the budget: nothing is weighed
// within budget_w - margin_w, the pick was measured, and its corrected prediction with its
// probes is over the budget. False where the sizes disagree or a figure is not finite.
bool held_over_budget(const HeldSelection& held);

// Whether to draw the cheapest for one window: held_over_budget, and the range's low end
// (cheapest_w) plus the sensor's scatter margin is under the pick's corrected prediction.
bool explore_where_held(const HeldSelection& held, double cheapest_w, double scatter_w);

}  // namespace glbudget::loop
