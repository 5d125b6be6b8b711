#include "glbudget/loop/range_end_hold.hpp"

#include <cmath>

namespace glbudget::loop {

bool RangeEndHold::observe(std::size_t end, double change_w, bool seen, double above_idle_w) {
  if (seen) {
    carried_w_.erase(end);
    return false;
  }
  if (!std::isfinite(change_w) || !(above_idle_w > 0.0) || !std::isfinite(above_idle_w)) return false;
  if (!(std::abs(change_w) > kImplausibleShare * above_idle_w)) return false;
  carried_w_[end] -= change_w;
  return true;
}

void RangeEndHold::keep_only(std::size_t top) {
  std::erase_if(carried_w_, [&](const auto& carried) { return carried.first != top; });
}

double RangeEndHold::carried_w(std::size_t end) const {
  const auto found = carried_w_.find(end);
  return found == carried_w_.end() ? 0.0 : found->second;
}

}  // namespace glbudget::loop
