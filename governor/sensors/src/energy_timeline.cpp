#include "glbudget/sensors/energy_timeline.hpp"

namespace glbudget::sensors {

namespace {
constexpr auto relaxed = std::memory_order_relaxed;
// The reader looks this many points back at most; the writer may publish up to
// capacity - lookback points while a read is in progress before slots could be reused.
constexpr std::uint64_t lookback = 8;
static_assert(lookback * 2 < EnergyTimeline::capacity);
}  // namespace

void EnergyTimeline::publish(const EnergyPoint& point) {
  const std::uint64_t n = published_.load(relaxed);
  Slot& slot = slots_[n % capacity];
  slot.t_ns.store(point.t_ns, relaxed);
  slot.energy_j.store(point.energy_j, relaxed);
  slot.segment.store(point.segment, relaxed);
  published_.store(n + 1, std::memory_order_release);
}

EnergyPoint EnergyTimeline::load(std::uint64_t index) const {
  const Slot& slot = slots_[index % capacity];
  return EnergyPoint{slot.t_ns.load(relaxed), slot.energy_j.load(relaxed), slot.segment.load(relaxed)};
}

std::optional<EnergyPoint> EnergyTimeline::energy_at(std::int64_t t_ns, std::int64_t max_extrapolation_ns) const {
  for (;;) {
    const std::uint64_t n = published_.load(std::memory_order_acquire);
    if (n == 0) return std::nullopt;
    const std::uint64_t oldest = n > lookback ? n - lookback : 0;

    std::optional<EnergyPoint> result;
    EnergyPoint later = load(n - 1);
    if (t_ns >= later.t_ns) {
      if (t_ns == later.t_ns) {
        result = later;
      } else if (t_ns - later.t_ns <= max_extrapolation_ns && n >= 2) {
        // Extrapolation needs the segment's current rate, hence two points of it.
        const EnergyPoint earlier = load(n - 2);
        if (earlier.segment == later.segment && later.t_ns > earlier.t_ns) {
          const double slope = (later.energy_j - earlier.energy_j) / static_cast<double>(later.t_ns - earlier.t_ns);
          result = EnergyPoint{t_ns, later.energy_j + slope * static_cast<double>(t_ns - later.t_ns), later.segment};
        }
      }
    } else {
      // t is inside the recent curve (the writer published after the caller read its clock).
      for (std::uint64_t i = n - 1; i > oldest; --i) {
        const EnergyPoint earlier = load(i - 1);
        if (earlier.t_ns <= t_ns) {
          if (earlier.segment == later.segment) {
            const double f = static_cast<double>(t_ns - earlier.t_ns) / static_cast<double>(later.t_ns - earlier.t_ns);
            result = EnergyPoint{t_ns, earlier.energy_j + f * (later.energy_j - earlier.energy_j), later.segment};
          } else if (earlier.t_ns == t_ns) {
            result = earlier;  // the last point of a segment
          }
          // Else t falls between two segments, where the curve is broken: its energy is unknown.
          break;
        }
        later = earlier;
      }
    }
    // Retry if the writer may have reused a slot we read (it would need to lap the ring).
    if (published_.load(std::memory_order_acquire) - oldest < capacity - lookback) return result;
  }
}

}  // namespace glbudget::sensors
