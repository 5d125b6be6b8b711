#pragma once
// Turns raw readings into points of a cumulative energy curve, dropping and counting bad
// samples. Pure logic (no clock, no I/O), driven by the sampling thread.
#include <cstdint>
#include <optional>
#include <string>

#include "glbudget/sensors/source.hpp"

namespace glbudget::sensors {

struct FaultCounts {
  std::uint64_t read_error = 0;  // the source vanished or refused a read
  std::uint64_t garbage = 0;     // not a number, NaN/inf, negative, or physically implausible
  std::uint64_t backwards = 0;   // an energy counter (or a meter's clock) went backwards
  std::uint64_t stalled = 0;     // no new data for longer than the stall timeout
  std::uint64_t total() const { return read_error + garbage + backwards + stalled; }
};

enum class Fault { read_error, garbage, backwards, stalled };
const char* to_string(Fault);

// One point of the cumulative energy curve. Points of different segments must not be
// differenced: a new segment starts wherever the continuity of the counter was lost.
struct EnergyPoint {
  std::int64_t t_ns = 0;
  double energy_j = 0.0;
  std::uint32_t segment = 0;
};

struct IntegratorLimits {
  double max_plausible_w = 5000.0;                // above this a sample is garbage
  std::int64_t stall_timeout_ns = 1'000'000'000;  // no new data for this long: stalled
};

class EnergyIntegrator {
 public:
  explicit EnergyIntegrator(IntegratorLimits limits = {}) : limits_(limits) {}

  struct Outcome {
    std::optional<EnergyPoint> point;  // to publish, if any (also marks where a segment breaks)
    std::optional<Fault> fault;        // set when the sample was dropped
    std::string detail;                // why, for the first message of each kind
  };
  // t_ns must come from one monotonic clock.
  Outcome accept(std::int64_t t_ns, const Reading& reading);

  const FaultCounts& faults() const { return faults_; }

 private:
  Outcome accept_reading(std::int64_t t_ns, const Reading& reading, bool stalled);
  Outcome drop(Fault fault, std::string detail);
  Outcome drop_stalled(std::int64_t t_ns, const char* what);
  std::optional<EnergyPoint> break_continuity(std::int64_t t_ns);
  Outcome start_segment(std::int64_t t_ns, double value);

  IntegratorLimits limits_;
  FaultCounts faults_;
  bool have_previous_ = false;
  bool continuity_lost_ = false;
  std::int64_t previous_t_ns_ = 0;
  double previous_value_ = 0.0;
  double energy_j_ = 0.0;
  std::uint32_t segment_ = 0;
};

}  // namespace glbudget::sensors
