#include "glbudget/loop/error_selection.hpp"

#include <cmath>
#include <limits>

namespace glbudget::loop {

model::Selection select_within_error(std::span<const double> predicted_power_w, std::span<const double> error,
                                     double error_budget) {
  model::Selection selection;
  selection.budget_w = std::numeric_limits<double>::infinity();
  bool found = false;
  bool any_best = false;
  std::size_t best = 0;  // lowest error, the fallback
  for (std::size_t i = 0; i < predicted_power_w.size(); ++i) {
    const double p = predicted_power_w[i];
    const double e = error[i];
    if (std::isnan(p) || std::isnan(e)) continue;
    if (!any_best || e < error[best] || (e == error[best] && p < predicted_power_w[best])) {
      best = i;
      any_best = true;
    }
    if (!(e <= error_budget)) continue;
    const double chosen_p = predicted_power_w[selection.index];
    if (!found || p < chosen_p || (p == chosen_p && e < error[selection.index])) {
      selection.index = i;
      found = true;
    }
  }
  if (!found) {
    selection.index = best;
    selection.within_budget = false;
  }
  return selection;
}

}  // namespace glbudget::loop
