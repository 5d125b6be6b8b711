#pragma once
// Configuration selection of paper §6.1: argmin estimated error subject to predicted power
// within the budget. The budget is either a share of the scene's range of predicted power
// (the paper's definition: 40% admits P <= P_min + 0.4 (P_max - P_min), where P_min and P_max
// are the lowest and highest predicted power over all configurations) or absolute watts.
#include <cstddef>
#include <optional>
#include <span>
#include <string_view>

namespace glbudget::model {

struct Budget {
  enum class Kind { Off, ShareOfRange, Watts };
  Kind kind = Kind::Off;
  double value = 0.0;  // share in [0, 1], or watts
};

// "40%", "35W" (or "35w", "35 W"), "off" or "". Anything else: one `glbudget:` line on stderr
// and std::nullopt, so the caller keeps its default.
std::optional<Budget> parse_budget(std::string_view text);

// An error budget (GLBUDGET_ERROR, `glbudget run --error`): 1 - SSIM in [0, 1], e.g. "0.02",
// spaces around it allowed. Anything else: std::nullopt, and the caller says why in its words.
std::optional<double> parse_error_budget(std::string_view text);

// Power limit in watts for this set of predictions; +inf when the budget is off. A share of
// the range runs from the lowest predicted power to, with `error`, the predicted power of the
// best-quality configuration (the highest among those of least error), else the highest
// predicted power. Beyond the paper, which takes the highest: a configuration of lower
// quality predicted above the best one is a misprediction (a level the model has not seen
// drawn), and taking it as the top would raise every budget with it.
double budget_watts(const Budget& budget, std::span<const double> predicted_power_w,
                    std::span<const double> error = {});

// The configuration at the top of a share of the range (see budget_watts); SIZE_MAX when no
// prediction is finite.
std::size_t range_top(std::span<const double> predicted_power_w, std::span<const double> error);

struct Selection {
  std::size_t index = 0;  // chosen configuration
  double budget_w = 0.0;
  bool within_budget = true;  // false: nothing fits, the lowest-power configuration was taken
};

// Lowest error among configurations with power <= budget (inclusive, so 100% admits the most
// expensive one and 0% the cheapest); ties go to lower power. NaN errors rank last, NaN powers
// are never admitted. Requires predicted_power_w.size() == error.size() > 0.
// margin_w > 0 admits only power <= budget - margin while any configuration is that far
// under the budget; when none is, the lowest-power configuration, which comes closest to
// keeping the margin, if it is within the budget (budget_w is the budget either way).
Selection select_configuration(std::span<const double> predicted_power_w, std::span<const double> error,
                               const Budget& budget, double margin_w = 0.0);
// The same under a limit already in watts (budget_w, +inf: none).
Selection select_configuration(std::span<const double> predicted_power_w, std::span<const double> error,
                               double budget_w, double margin_w = 0.0);

}  // namespace glbudget::model
