#include <pthread.h>
#include <time.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <limits>
#include <mutex>

#include "glbudget/sensors/sensor.hpp"

namespace glbudget::sensors {

std::int64_t monotonic_now_ns() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

PowerSensor::PowerSensor(std::unique_ptr<Source> source, SamplerOptions options)
    : source_(std::move(source)),
      name_(source_->name()),
      description_(source_->description()),
      estimate_(source_->is_estimate()),
      read_at_swap_(source_->energy_now_j(monotonic_now_ns()).has_value()),
      options_(options),
      integrator_(options.limits) {
  if (!read_at_swap_) thread_ = std::jthread([this](std::stop_token stop) { sample_loop(stop); });
}

PowerSensor::~PowerSensor() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void PowerSensor::sample_loop(std::stop_token stop) {
  pthread_setname_np(pthread_self(), "glbudget-sensor");
  std::mutex mutex;
  std::condition_variable_any wake;
  std::unique_lock lock(mutex);
  auto next = std::chrono::steady_clock::now();
  while (!stop.stop_requested()) {
    sample_once();
    next += options_.period;
    // A starved thread resynchronises instead of firing a burst of catch-up samples.
    if (next < std::chrono::steady_clock::now()) next = std::chrono::steady_clock::now();
    wake.wait_until(lock, stop, next, [] { return false; });
  }
}

void PowerSensor::sample_once() {
  const std::int64_t now = monotonic_now_ns();
  const Reading reading = source_->read(now);
  const auto outcome = integrator_.accept(now, reading);
  if (outcome.point) timeline_.publish(*outcome.point);
  if (outcome.fault) {
    const FaultCounts& counts = integrator_.faults();
    fault_counts_[0].store(counts.read_error, std::memory_order_relaxed);
    fault_counts_[1].store(counts.garbage, std::memory_order_relaxed);
    fault_counts_[2].store(counts.backwards, std::memory_order_relaxed);
    fault_counts_[3].store(counts.stalled, std::memory_order_relaxed);
    report_fault(*outcome.fault, outcome.detail);
  }
}

void PowerSensor::report_fault(Fault fault, const std::string& detail) {
  bool& reported = fault_reported_[static_cast<int>(fault)];
  if (reported) return;
  reported = true;
  std::fprintf(stderr, "glbudget: sensor %.*s: sample dropped (%s: %s); further drops are only counted\n",
               static_cast<int>(name_.size()), name_.data(), to_string(fault), detail.c_str());
}

FaultCounts PowerSensor::faults() const {
  auto count = [this](int i) { return fault_counts_[i].load(std::memory_order_relaxed); };
  return FaultCounts{count(0), count(1), count(2), count(3)};
}

FrameEnergy PowerSensor::on_swap(std::int64_t now_ns) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  FrameEnergy frame{false, nan, nan, name_, estimate_, 0};

  const std::uint64_t dropped = faults().total();
  frame.dropped_samples = dropped - previous_dropped_;
  previous_dropped_ = dropped;

  std::optional<EnergyPoint> now;
  if (read_at_swap_) {
    if (const auto energy = source_->energy_now_j(now_ns)) now = EnergyPoint{now_ns, *energy, 0};
  } else {
    // Sources with slow updates (a meter writing at 10 Hz, a counter refreshed every 100 ms)
    // publish points rarely; extrapolation covers them up to the stall timeout, past which
    // the integrator has declared the source stalled anyway.
    now = timeline_.energy_at(now_ns, options_.limits.stall_timeout_ns);
  }
  if (!now) {
    have_previous_swap_ = false;
    return frame;
  }
  // Differencing against the value reported at the previous swap (not a re-interpolation of
  // it) keeps the per-frame energies summing exactly to the counter's total.
  EnergyPoint reported = *now;
  if (have_previous_swap_ && previous_swap_.segment == now->segment && now_ns > previous_swap_.t_ns) {
    // An extrapolation may have overshot the curve: report zero until it catches up.
    reported.energy_j = std::max(now->energy_j, previous_swap_.energy_j);
    frame.valid = true;
    frame.energy_j = reported.energy_j - previous_swap_.energy_j;
    frame.mean_power_w = frame.energy_j / (static_cast<double>(now_ns - previous_swap_.t_ns) * 1e-9);
  }
  previous_swap_ = reported;
  have_previous_swap_ = true;
  return frame;
}

}  // namespace glbudget::sensors
