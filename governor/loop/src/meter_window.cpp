#include "glbudget/loop/meter_window.hpp"

namespace glbudget::loop {

void MeterWindow::start(std::int64_t time_ns) {
  window_start_ns_ = time_ns;
  energy_j_ = seconds_ = budget_sum_w_ = 0.0;
  probes_ = frames_ = budgeted_frames_ = 0;
}

std::optional<MeterWindow::Reading> MeterWindow::add(std::int64_t time_ns, double power_w, bool probe,
                                                     double budget_w) {
  if (!started_ || time_ns < window_start_ns_) {
    // The first frame only marks the time: its interval began before the configuration settled.
    started_ = true;
    last_ns_ = time_ns;
    start(time_ns);
    return std::nullopt;
  }
  if (time_ns < last_ns_) return std::nullopt;
  const double dt = static_cast<double>(time_ns - last_ns_) * 1e-9;
  last_ns_ = time_ns;
  ++frames_;
  probes_ += probe ? 1 : 0;
  if (std::isfinite(power_w)) {
    energy_j_ += power_w * dt;
    seconds_ += dt;
  }
  if (std::isfinite(budget_w)) {
    budget_sum_w_ += budget_w;
    ++budgeted_frames_;
  }
  // In the clock's own nanoseconds: a second of 100-ms frames summed in double falls short of 1.
  const std::int64_t elapsed_ns = time_ns - window_start_ns_;
  if (static_cast<double>(elapsed_ns) < window_s_ * 1e9) return std::nullopt;
  Reading reading;
  // Half the window without power (a sensor that skips) is not a meter's reading.
  if (seconds_ >= 0.5e-9 * static_cast<double>(elapsed_ns) && seconds_ > 0.0) reading.watts = energy_j_ / seconds_;
  reading.probes = probes_;
  reading.frames = frames_;
  reading.span_s = static_cast<double>(elapsed_ns) * 1e-9;
  if (budgeted_frames_ > 0) reading.budget_w = budget_sum_w_ / budgeted_frames_;
  start(time_ns);
  return reading;
}

}  // namespace glbudget::loop
