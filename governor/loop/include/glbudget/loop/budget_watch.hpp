#pragma once

#include <cstdint>
#include <deque>
#include <optional>

#include "glbudget/loop/meter_window.hpp"

namespace glbudget::loop {

// Beyond the paper: whether a power budget is being kept at all, as a meter on the wall reads
// the run. Every frame after the first selection, whatever it drew (transitions, probes and
// explorations included), falls in a MeterWindow's wall-clock windows of window_s; once `over`
// of the last `of` windows measured more than their budget (the mean of their frames': a
// selection may move it several times a second), the run is not keeping its budget, and the
// user is told once (Governor::notes). The usual causes: a budget under what the cheapest
// configuration draws, and frames that nothing paces, where a cheaper configuration turns the time it saves into
// more frames at the same power. A window counts as over by more than kTolerance of its
// budget: the cpu estimate scatters by 2-6 % between identical runs, and an app idle at its
// pace has a range that narrow (glxgears at 10 fps: 10.5-10.8 W).
class BudgetWatch {
 public:
  struct Verdict {
    double budget_w = 0.0;      // the windows' mean budget
    double measured_w = 0.0;    // the windows' mean power
    double frames_per_s = 0.0;  // the windows' mean frame rate
    int over = 0;               // windows over the budget
    int of = 0;                 // windows watched
  };

  explicit BudgetWatch(double window_s = 1.0, int of = 10, int over = 8)
      : of_(of), over_needed_(over), meter_(window_s) {}

  static constexpr double kTolerance = 0.03;

  // A frame presented at time_ns with its mean power since the previous one (NaN: none) under
  // budget_w (not finite: no power budget in force yet, and the windows start afresh). The
  // verdict comes once, with the first window that leaves `over` of the last `of` over.
  std::optional<Verdict> add(std::int64_t time_ns, double power_w, double budget_w);

 private:
  int of_;
  int over_needed_;
  bool said_ = false;
  MeterWindow meter_;
  std::deque<MeterWindow::Reading> windows_;
};

}  // namespace glbudget::loop
