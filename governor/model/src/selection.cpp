#include "glbudget/model/selection.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <limits>
#include <string>

namespace glbudget::model {
namespace {

std::string_view trim(std::string_view text) {
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.front()))) text.remove_prefix(1);
  while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.remove_suffix(1);
  return text;
}

std::optional<double> parse_number(std::string_view text) {
  text = trim(text);
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

std::optional<Budget> reject(std::string_view text, const char* why) {
  std::cerr << "glbudget: power budget \"" << text << "\" " << why
            << " (expected e.g. 40% or 35W or off); ignoring it\n";
  return std::nullopt;
}

}  // namespace

std::optional<Budget> parse_budget(std::string_view text) {
  const std::string_view value = trim(text);
  if (value.empty() || value == "off" || value == "OFF" || value == "Off") return Budget{};
  const char unit = value.back();
  const std::optional<double> number = parse_number(value.substr(0, value.size() - 1));
  if (unit == '%') {
    if (!number) return reject(text, "is not a number");
    if (*number < 0.0 || *number > 100.0) return reject(text, "is outside 0%..100%");
    return Budget{Budget::Kind::ShareOfRange, *number / 100.0};
  }
  if (unit == 'W' || unit == 'w') {
    if (!number) return reject(text, "is not a number");
    if (*number < 0.0) return reject(text, "is negative");
    return Budget{Budget::Kind::Watts, *number};
  }
  return reject(text, "has no unit");
}

std::optional<double> parse_error_budget(std::string_view text) {
  const std::optional<double> e = parse_number(text);
  if (!e || *e < 0.0 || *e > 1.0) return std::nullopt;
  return *e;
}

namespace {

struct Range {
  double lowest = std::numeric_limits<double>::infinity();
  double highest = -std::numeric_limits<double>::infinity();
  std::size_t top = SIZE_MAX;  // the configuration at `highest`
  bool finite() const { return lowest <= highest; }
};

// From the lowest prediction to the best-quality configuration's (the highest among those of
// least error), else to the highest prediction.
Range range_of(std::span<const double> predicted_power_w, std::span<const double> error) {
  Range r;
  for (std::size_t i = 0; i < predicted_power_w.size(); ++i) {
    const double p = predicted_power_w[i];
    if (std::isnan(p)) continue;
    r.lowest = std::min(r.lowest, p);
    if (p > r.highest) r.highest = p, r.top = i;
  }
  if (!r.finite() || error.size() != predicted_power_w.size()) return r;
  double least_error = std::numeric_limits<double>::infinity(), best = std::nan("");
  std::size_t best_index = SIZE_MAX;
  for (std::size_t i = 0; i < error.size(); ++i) {
    const double p = predicted_power_w[i], e = error[i];
    if (std::isnan(p) || std::isnan(e)) continue;
    if (e < least_error || (e == least_error && p > best)) least_error = e, best = p, best_index = i;
  }
  if (best >= r.lowest) r.highest = best, r.top = best_index;
  return r;
}

// Written as a convex combination so that 0% and 100% give exactly lowest and highest.
double share_of(const Range& r, double share) { return (1.0 - share) * r.lowest + share * r.highest; }

}  // namespace

double budget_watts(const Budget& budget, std::span<const double> predicted_power_w, std::span<const double> error) {
  switch (budget.kind) {
    case Budget::Kind::Off:
      return std::numeric_limits<double>::infinity();
    case Budget::Kind::Watts:
      return budget.value;
    case Budget::Kind::ShareOfRange:
      break;
  }
  const Range r = range_of(predicted_power_w, error);
  return r.finite() ? share_of(r, budget.value) : std::numeric_limits<double>::infinity();
}

std::size_t range_top(std::span<const double> predicted_power_w, std::span<const double> error) {
  const Range r = range_of(predicted_power_w, error);
  return r.finite() ? r.top : SIZE_MAX;
}

Selection select_configuration(std::span<const double> predicted_power_w, std::span<const double> error,
                               const Budget& budget, double margin_w) {
  return select_configuration(predicted_power_w, error, budget_watts(budget, predicted_power_w, error), margin_w);
}

Selection select_configuration(std::span<const double> predicted_power_w, std::span<const double> error,
                               double budget_w, double margin_w) {
  Selection selection;
  selection.budget_w = budget_w;
  const auto rank = [](double e) { return std::isnan(e) ? std::numeric_limits<double>::infinity() : e; };

  const auto lowest_error_within = [&](double limit, std::size_t* index) {
    bool found = false;
    for (std::size_t i = 0; i < predicted_power_w.size(); ++i) {
      const double p = predicted_power_w[i];
      if (!(p <= limit)) continue;
      const double e = rank(error[i]);
      const double best_e = rank(error[*index]);
      if (!found || e < best_e || (e == best_e && p < predicted_power_w[*index])) {
        *index = i;
        found = true;
      }
    }
    return found;
  };
  const bool margined = std::isfinite(margin_w) && margin_w > 0.0 && std::isfinite(selection.budget_w);
  if (margined && lowest_error_within(selection.budget_w - margin_w, &selection.index)) return selection;

  std::size_t cheapest = 0;
  for (std::size_t i = 0; i < predicted_power_w.size(); ++i) {
    const double p = predicted_power_w[i];
    if (!std::isnan(p) && (std::isnan(predicted_power_w[cheapest]) || p < predicted_power_w[cheapest] ||
                           (p == predicted_power_w[cheapest] && rank(error[i]) < rank(error[cheapest]))))
      cheapest = i;
  }
  // The margin is wider than the room under the budget: the configuration that comes closest
  // to keeping it. One at the budget itself would be over it in about every other window.
  if (margined && predicted_power_w[cheapest] <= selection.budget_w) {
    selection.index = cheapest;
    return selection;
  }
  if (lowest_error_within(selection.budget_w, &selection.index)) return selection;
  selection.index = cheapest;
  selection.within_budget = false;
  return selection;
}

}  // namespace glbudget::model
