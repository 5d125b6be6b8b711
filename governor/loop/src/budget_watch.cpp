#include "glbudget/loop/budget_watch.hpp"

#include <cmath>
#include <limits>

namespace glbudget::loop {

void BudgetWatch::restart(std::int64_t time_ns) {
  started_ = true;
  last_ns_ = window_start_ns_ = time_ns;
  energy_j_ = seconds_ = budget_sum_w_ = 0.0;
  frames_ = 0;
}

std::optional<BudgetWatch::Verdict> BudgetWatch::add(std::int64_t time_ns, double power_w, double budget_w) {
  if (said_) return std::nullopt;
  if (!std::isfinite(budget_w)) {
    started_ = false;
    windows_.clear();
    return std::nullopt;
  }
  // The first frame, or one from a new clock (a new context's frames): its interval is unknown.
  if (!started_ || time_ns < last_ns_) {
    restart(time_ns);
    return std::nullopt;
  }
  const double dt = static_cast<double>(time_ns - last_ns_) * 1e-9;
  last_ns_ = time_ns;
  ++frames_;
  budget_sum_w_ += budget_w;
  if (std::isfinite(power_w)) {
    energy_j_ += power_w * dt;
    seconds_ += dt;
  }
  const double span = static_cast<double>(time_ns - window_start_ns_) * 1e-9;
  if (span < window_s_) return std::nullopt;
  windows_.push_back({seconds_ > 0.0 ? energy_j_ / seconds_ : std::numeric_limits<double>::quiet_NaN(), frames_ / span,
                      budget_sum_w_ / frames_});
  restart(time_ns);
  if (static_cast<int>(windows_.size()) > of_) windows_.pop_front();
  if (static_cast<int>(windows_.size()) < of_) return std::nullopt;

  Verdict v;
  v.of = of_;
  double watts = 0.0, rate = 0.0, budget = 0.0;
  int measured = 0;
  for (const Window& w : windows_) {
    rate += w.frames_per_s;
    if (!std::isfinite(w.watts)) continue;
    watts += w.watts;
    budget += w.budget_w;
    ++measured;
    if (w.watts > w.budget_w * (1.0 + kTolerance)) ++v.over;
  }
  if (v.over < over_needed_) return std::nullopt;
  said_ = true;
  v.measured_w = watts / measured;
  v.budget_w = budget / measured;
  v.frames_per_s = rate / static_cast<double>(windows_.size());
  return v;
}

}  // namespace glbudget::loop
