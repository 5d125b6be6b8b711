#include "glbudget/loop/probe_order.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::loop {

std::size_t next_probe(std::span<const ProbeCandidate> candidates, std::uint64_t now) {
  const auto known = [](const ProbeCandidate& c) {
    return c.last_frame != 0 && std::isfinite(c.error) && c.error >= 0;
  };
  double largest = 0.0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const ProbeCandidate& c = candidates[k];
    if (!c.in_scene) continue;
    if (!known(c)) return k;
    largest = std::max(largest, c.error);
  }
  const double floor = std::max(kErrorFloor, largest / 10.0);
  std::size_t pick = candidates.size();
  double top = -1.0;
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const ProbeCandidate& c = candidates[k];
    if (!c.in_scene) continue;
    const double age = now > c.last_frame ? static_cast<double>(now - c.last_frame) : 0.0;
    const double priority = std::max(c.error, floor) * age;
    if (priority > top) {
      top = priority;
      pick = k;
    }
  }
  return pick;
}

}  // namespace glbudget::loop
