#pragma once
// Beyond the paper: a quality-probe frame draws the frame a second time, so its power is
// not any configuration's and the model never learns from it; but the user's meter sees it,
// in every window a probe falls into. ProbeOverhead measures what probes add to the mean
// power of all frames, probe frames included: each probe's excess over the frames drawn just
// before it, summed over the probe frame and the frame after it (the probe's image is
// compared one frame late, behind a fence), times the share of frames that are probes. A
// selection keeps it under the budget besides the spread's margin, and windows are held to
// the budget with it.
#include <cstddef>

namespace glbudget::loop {

class ProbeOverhead {
 public:
  // Every frame, in order; power NaN when not measured.
  void add(bool probe, double power_w);
  // The frame last added is a probe's or the one after it: its power is not its
  // configuration's own.
  bool in_span() const { return last_in_span_; }

  // Watts the probes add to the mean of all frames (>= 0; 0 before a probe with power).
  double watts() const;
  // The mean excess of a probe (its frame and the next) over the frames before it (may be
  // negative), and the share of recent frames that were probes.
  double excess_w() const { return excess_w_; }
  double share() const { return frames_ > 0.0 ? probes_ / frames_ : 0.0; }
  std::size_t probes_measured() const { return measured_; }

 private:
  void close_span();

  double recent_w_ = 0.0;  // the frames before, exponentially (about 8 frames)
  bool have_recent_ = false;
  // The probe being measured: frames of its span still to come, and its excess so far.
  int span_left_ = 0;
  double span_excess_w_ = 0.0;
  bool span_measured_ = false;
  bool last_in_span_ = false;
  double excess_w_ = 0.0;  // the probes' excess, exponentially (about 4 probes)
  std::size_t measured_ = 0;
  double probes_ = 0.0, frames_ = 0.0;  // decaying counts (about 200 frames)
};

}  // namespace glbudget::loop
