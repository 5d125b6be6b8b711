#include "glbudget/loop/probe_overhead.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::loop {
namespace {
constexpr double kRecentWeight = 1.0 / 8.0;
constexpr double kExcessWeight = 1.0 / 4.0;
constexpr double kShareDecay = 1.0 - 1.0 / 200.0;
constexpr int kSpanFrames = 2;  // the probe frame and the one that reads its comparison back
}  // namespace

void ProbeOverhead::close_span() {
  if (span_measured_) {
    excess_w_ = measured_ == 0 ? span_excess_w_ : excess_w_ + kExcessWeight * (span_excess_w_ - excess_w_);
    ++measured_;
  }
  span_left_ = 0;
  span_excess_w_ = 0.0;
  span_measured_ = false;
}

void ProbeOverhead::add(bool probe, double power_w) {
  // Decaying counts rather than a running mean, so that the share is right from the first
  // frames and follows a probe period changed mid-run.
  probes_ = probes_ * kShareDecay + (probe ? 1.0 : 0.0);
  frames_ = frames_ * kShareDecay + 1.0;
  if (probe) {
    close_span();
    span_left_ = kSpanFrames;
  }
  const bool finite = std::isfinite(power_w);
  last_in_span_ = span_left_ > 0;
  if (span_left_ > 0) {
    // The probe frame's power must be measured for the span to count; the next frame's
    // excess is added when it is.
    if (finite && have_recent_ && (probe || span_measured_)) {
      span_excess_w_ += power_w - recent_w_;
      span_measured_ = true;
    }
    if (--span_left_ == 0) close_span();
    return;
  }
  if (!finite) return;
  recent_w_ = have_recent_ ? recent_w_ + kRecentWeight * (power_w - recent_w_) : power_w;
  have_recent_ = true;
}

double ProbeOverhead::watts() const { return measured_ == 0 ? 0.0 : std::max(0.0, excess_w_) * share(); }

}  // namespace glbudget::loop
