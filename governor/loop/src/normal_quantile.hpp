#pragma once

namespace glbudget::loop {

// The standard normal quantile: the z with P(N(0,1) <= z) = p, p clamped to [1e-9, 1 - 1e-9].
double normal_quantile(double p);

}  // namespace glbudget::loop
