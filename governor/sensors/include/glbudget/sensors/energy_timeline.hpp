#pragma once
// The recent cumulative energy curve, shared between one writer (the sampling thread) and
// one reader (the render thread). Lock-free: the reader never waits for the writer.
#include <array>
#include <atomic>
#include <cstdint>
#include <optional>

#include "glbudget/sensors/energy_integrator.hpp"

namespace glbudget::sensors {

class EnergyTimeline {
 public:
  static constexpr std::size_t capacity = 64;

  void publish(const EnergyPoint& point);  // writer thread only

  // Energy of the curve at time t: interpolated between the points around t, or extrapolated
  // at the latest slope when t is past the newest point by no more than max_extrapolation_ns.
  // Empty when no point is recent enough (a stale sensor), when the newest segment has a
  // single point (no rate known yet), when t falls between two segments (a break in the
  // curve), or when t is older than the last few points.
  // Reader thread only.
  std::optional<EnergyPoint> energy_at(std::int64_t t_ns, std::int64_t max_extrapolation_ns) const;

 private:
  struct Slot {
    std::atomic<std::int64_t> t_ns{0};
    std::atomic<double> energy_j{0.0};
    std::atomic<std::uint32_t> segment{0};
  };
  EnergyPoint load(std::uint64_t index) const;

  std::array<Slot, capacity> slots_;
  std::atomic<std::uint64_t> published_{0};
};

}  // namespace glbudget::sensors
