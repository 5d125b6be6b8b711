#include "glbudget/quality/simd_target.hpp"

#include <hwy/highway.h>

#include <stdexcept>

namespace glbudget::quality {

// Compiled with the same flags as ssim_kernels.cpp, so HWY_TARGETS here is the set its
// dispatch table holds.
std::vector<std::string> simd_targets() {
  std::vector<std::string> names;
  for (const int64_t target : hwy::SupportedAndGeneratedTargets()) names.emplace_back(hwy::TargetName(target));
  return names;
}

std::string simd_target() {
  const std::vector<std::string> names = simd_targets();
  return names.empty() ? std::string("none") : names.front();
}

void pin_simd_target(std::string_view name) {
  if (name.empty()) {
    hwy::SetSupportedTargetsForTest(0);
    return;
  }
  hwy::SetSupportedTargetsForTest(0);  // choose among every target, not the last pinned one
  for (const int64_t target : hwy::SupportedAndGeneratedTargets())
    if (name == hwy::TargetName(target)) {
      hwy::SetSupportedTargetsForTest(target);
      return;
    }
  throw std::invalid_argument("no SIMD target \"" + std::string(name) + "\" on this machine");
}

}  // namespace glbudget::quality
