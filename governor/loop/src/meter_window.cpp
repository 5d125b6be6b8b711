#include "glbudget/loop/meter_window.hpp"

#include <cmath>

namespace glbudget::loop {

std::optional<MeterWindow::Reading> MeterWindow::add(std::int64_t time_ns, double power_w, bool probe) {
  if (!started_ || time_ns < window_start_ns_) {
    // The first frame only marks the time: its interval began before the configuration settled.
    started_ = true;
    last_ns_ = window_start_ns_ = time_ns;
    energy_j_ = seconds_ = 0.0;
    probes_ = 0;
    return std::nullopt;
  }
  if (time_ns < last_ns_) return std::nullopt;
  const double dt = static_cast<double>(time_ns - last_ns_) * 1e-9;
  last_ns_ = time_ns;
  probes_ += probe ? 1 : 0;
  if (std::isfinite(power_w)) {
    energy_j_ += power_w * dt;
    seconds_ += dt;
  }
  // In the clock's own nanoseconds: a second of 100-ms frames summed in double falls short of 1.
  const std::int64_t elapsed_ns = time_ns - window_start_ns_;
  if (static_cast<double>(elapsed_ns) < window_s_ * 1e9) return std::nullopt;
  // Half the window without power (a sensor that skips) is not a meter's reading.
  const bool measured = seconds_ >= 0.5e-9 * static_cast<double>(elapsed_ns) && seconds_ > 0.0;
  const Reading reading{measured ? energy_j_ / seconds_ : 0.0, probes_};
  energy_j_ = seconds_ = 0.0;
  probes_ = 0;
  window_start_ns_ = time_ns;
  if (!measured) return std::nullopt;
  return reading;
}

}  // namespace glbudget::loop
