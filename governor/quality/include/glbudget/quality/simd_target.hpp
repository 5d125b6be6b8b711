#pragma once
// Which Highway target (instruction set) ssim() runs on. It picks the best this CPU supports at
// its first call; tests and benchmarks pin others to check and time each one. Pinning is
// process-wide and not meant to race with ssim() calls on other threads.
#include <string>
#include <string_view>
#include <vector>

namespace glbudget::quality {

// Targets compiled in and supported by this CPU, best first: e.g. AVX3_DL, AVX3, AVX2, SSE4,
// SSSE3, EMU128 (Highway's portable scalar emulation).
std::vector<std::string> simd_targets();
// The target ssim() uses now.
std::string simd_target();
// Pins one of simd_targets(); "" returns to the best. Throws std::invalid_argument otherwise.
void pin_simd_target(std::string_view name);

}  // namespace glbudget::quality
