#pragma once
// The dual of paper §6.1's selection: an error budget alone (GLBUDGET_ERROR) asks for the
// lowest power whose estimated error stays within it.
#include <span>

#include "glbudget/model/selection.hpp"

namespace glbudget::loop {

// Lowest predicted power among configurations with error <= error_budget (inclusive); ties go
// to lower error. NaN powers are never admitted, nor NaN errors. When nothing is admitted,
// the lowest-error configuration (the cheapest among equals) is taken with within_budget
// false. budget_w is +inf: no power limit. Requires power.size() == error.size() > 0.
model::Selection select_within_error(std::span<const double> predicted_power_w, std::span<const double> error,
                                     double error_budget);

}  // namespace glbudget::loop
