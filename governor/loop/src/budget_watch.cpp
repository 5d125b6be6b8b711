#include "glbudget/loop/budget_watch.hpp"

#include <cmath>

namespace glbudget::loop {

std::optional<BudgetWatch::Verdict> BudgetWatch::add(std::int64_t time_ns, double power_w, double budget_w) {
  if (said_) return std::nullopt;
  if (!std::isfinite(budget_w)) {
    meter_.interrupt();
    windows_.clear();
    return std::nullopt;
  }
  const std::optional<MeterWindow::Reading> closed = meter_.add(time_ns, power_w, false, budget_w);
  if (!closed) return std::nullopt;
  windows_.push_back(*closed);
  if (static_cast<int>(windows_.size()) > of_) windows_.pop_front();
  if (static_cast<int>(windows_.size()) < of_) return std::nullopt;

  Verdict v;
  v.of = of_;
  double watts = 0.0, rate = 0.0, budget = 0.0;
  int measured = 0;
  for (const MeterWindow::Reading& w : windows_) {
    rate += w.frames / w.span_s;
    if (!w.measured()) continue;
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
