#pragma once
// The power sensor as the shim uses it: open it once, call on_swap() at every buffer swap.
//
//   auto sensor = glbudget::sensors::open_sensor_from_environment();  // GLBUDGET_SENSOR
//   ...at each swap, on the render thread:
//   FrameEnergy e = sensor->on_swap(monotonic_now_ns());
//   if (e.valid) log(e.energy_j, e.mean_power_w, e.sensor, e.estimate, e.dropped_samples);
//
// A sampling thread reads the source every `period`; on_swap() only reads memory the thread
// published (lock-free, no I/O, no allocation), so it never stalls the frame. Sources that can
// be read exactly at any instant (the cpu estimate, see Source::energy_now_j) are read in
// on_swap() itself instead, with no thread.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <thread>

#include "glbudget/sensors/energy_timeline.hpp"
#include "glbudget/sensors/source.hpp"

namespace glbudget::sensors {

struct FrameEnergy {
  // False when no measurement covers the interval: the first swaps (the sampler needs two
  // samples), a sensor that failed, stalled or vanished since the previous swap, or a counter
  // that lost continuity (see dropped_samples). Then energy_j and mean_power_w are NaN and the
  // log leaves the fields empty.
  bool valid = false;
  double energy_j;                    // energy of the interval since the previous swap
  double mean_power_w;                // energy_j / interval
  std::string_view sensor;            // the source's name ("rapl", "cpu", ...); static storage
  bool estimate = false;              // modelled, not measured: label it so in logs and reports
  std::uint64_t dropped_samples = 0;  // samples dropped since the previous swap
};

struct SamplerOptions {
  std::chrono::nanoseconds period = std::chrono::milliseconds(5);
  IntegratorLimits limits;
};

class PowerSensor {
 public:
  PowerSensor(std::unique_ptr<Source> source, SamplerOptions options = {});
  ~PowerSensor();  // stops and joins the sampling thread
  PowerSensor(const PowerSensor&) = delete;
  PowerSensor& operator=(const PowerSensor&) = delete;

  // Render thread only. now_ns: CLOCK_MONOTONIC. Never blocks. The first valid frame needs
  // two samples before the previous swap (two sampling periods after construction).
  FrameEnergy on_swap(std::int64_t now_ns);

  std::string_view name() const { return name_; }
  bool is_estimate() const { return estimate_; }
  std::string description() const { return description_; }
  std::chrono::nanoseconds period() const { return options_.period; }
  FaultCounts faults() const;  // any thread

 private:
  void sample_loop(std::stop_token stop);
  void sample_once();
  void report_fault(Fault fault, const std::string& detail);

  std::unique_ptr<Source> source_;
  const std::string_view name_;  // static storage, see Source::name()
  const std::string description_;
  const bool estimate_;
  const bool read_at_swap_;  // Source::energy_now_j available: no sampling thread
  const SamplerOptions options_;
  EnergyIntegrator integrator_;  // sampling thread only
  EnergyTimeline timeline_;
  std::atomic<std::uint64_t> fault_counts_[4] = {};  // FaultCounts, in declaration order
  bool fault_reported_[4] = {};                      // sampling thread only: one stderr line per kind of fault

  // Render-thread state.
  bool have_previous_swap_ = false;
  EnergyPoint previous_swap_;
  std::uint64_t previous_dropped_ = 0;

  std::jthread thread_;  // last: started once everything above exists
};

std::int64_t monotonic_now_ns();

// Opens the sensor named by GLBUDGET_SENSOR (default "auto"; syntax in registry.hpp), sampled
// every GLBUDGET_SENSOR_PERIOD_MS milliseconds (1..1000, default 5).
// Bad values and unavailable sensors give one "glbudget:" line on stderr and fall back to
// "auto", which always ends at the cpu estimate. Returns null only if even that fails.
// With "auto" it says on stderr which sensor it picked.
std::unique_ptr<PowerSensor> open_sensor_from_environment();

// GLBUDGET_SENSOR_PERIOD_MS's value: whole milliseconds in 1..1000, nothing around them;
// std::nullopt otherwise.
std::optional<std::chrono::milliseconds> parse_sampling_period_ms(std::string_view text);

}  // namespace glbudget::sensors
