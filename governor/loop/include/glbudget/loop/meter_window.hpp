#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

namespace glbudget::loop {

// A power meter's window over the frames of one settled configuration: each frame's power held
// over its own interval (from the previous frame's time to its own), probe frames and the frames
// that finish their work included, as a meter on the wall reads them. PowerFeedback's windows
// leave those frames out (their power is not their configuration's own) and ProbeOverhead adds
// the probes' mean back; a window holding a probe burst can be over the budget while that mean
// says it is not. A window ends with the frame that reaches its length, whose whole interval it
// takes (at 10 frames a second a window is 1 to 1.1 s). BudgetWatch reads the whole run with it.
class MeterWindow {
 public:
  struct Reading {
    static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
    double watts = kNone;     // NaN: power for less than half the window, which no meter reads
    int probes = 0;           // probe frames in the window
    int frames = 0;           // frames whose intervals it holds
    double span_s = 0.0;      // from the frame before the first to the last
    double budget_w = kNone;  // the mean of its frames' budgets, where they were given one
    bool measured() const { return std::isfinite(watts); }
  };

  explicit MeterWindow(double window_s) : window_s_(window_s) {}

  // A frame of the settled configuration, under budget_w if one is given; the window it closes,
  // if it does, measured or not. A frame without power (NaN) moves the clock on without counting
  // its interval; one older than the last (frames handed over out of order) is skipped; one from
  // before the window (a new clock) starts afresh.
  std::optional<Reading> add(std::int64_t time_ns, double power_w, bool probe, double budget_w = Reading::kNone);
  // Not settled (a transition, another configuration, a hold, exploring): the next frame starts
  // afresh.
  void interrupt() { started_ = false; }

 private:
  void start(std::int64_t time_ns);

  double window_s_;
  bool started_ = false;
  std::int64_t last_ns_ = 0;
  std::int64_t window_start_ns_ = 0;
  double energy_j_ = 0.0;
  double seconds_ = 0.0;  // of intervals with power
  int probes_ = 0;
  int frames_ = 0;
  double budget_sum_w_ = 0.0;
  int budgeted_frames_ = 0;
};

}  // namespace glbudget::loop
