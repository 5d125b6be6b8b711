#include "glbudget/loop/held_exploration.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::loop {

bool held_over_budget(const HeldSelection& held) {
  const std::size_t n = held.weighed_w.size();
  if (!held.measured || held.measured->size() != n || held.power_w.size() != n || held.pick >= n) return false;
  if (!std::isfinite(held.budget_w) || !std::isfinite(held.margin_w) || !std::isfinite(held.probes_w)) return false;
  if (!(*held.measured)[held.pick]) return false;
  const double limit = held.budget_w - held.margin_w;
  if (std::any_of(held.weighed_w.begin(), held.weighed_w.end(), [&](double p) { return p <= limit; })) return false;
  return held.power_w[held.pick] + std::max(0.0, held.probes_w) > held.budget_w;
}

bool explore_where_held(const HeldSelection& held, double cheapest_w, double scatter_w) {
  if (!std::isfinite(cheapest_w) || !std::isfinite(scatter_w) || !held_over_budget(held)) return false;
  return cheapest_w + std::max(0.0, scatter_w) < held.power_w[held.pick];
}

}  // namespace glbudget::loop
