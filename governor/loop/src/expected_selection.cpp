#include "glbudget/loop/expected_selection.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::loop {

model::Selection select_at_expected_power(const model::Selection& guarded, std::span<const double> guarded_w,
                                          const std::vector<bool>& measured, std::span<const double> error,
                                          double budget_w, double margin_w, double lowered_w) {
  if (!(margin_w > 0.0) || !std::isfinite(margin_w) || !std::isfinite(budget_w) || !(lowered_w > 0.0) ||
      !std::isfinite(lowered_w) || guarded_w.empty() || measured.size() != guarded_w.size() ||
      error.size() != guarded_w.size() || guarded.index >= guarded_w.size())
    return guarded;
  const double limit = budget_w - margin_w;
  if (std::any_of(guarded_w.begin(), guarded_w.end(), [&](double p) { return p <= limit; })) return guarded;
  // The guard ranked a configuration it does not raise: one measured, which it can hold the
  // run to. A pick never measured is the guard's own (the cheapest even at its quantile).
  if (!measured[guarded.index]) return guarded;
  std::vector<double> expected(guarded_w.begin(), guarded_w.end());
  for (std::size_t i = 0; i < expected.size(); ++i)
    if (!measured[i]) expected[i] -= lowered_w;
  return model::select_configuration(expected, error, budget_w, margin_w);
}

}  // namespace glbudget::loop
