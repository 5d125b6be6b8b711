#pragma once
// A power source: one per kind of hardware counter. Sources only read; the Sampler
// (sampler.hpp) turns their readings into a cumulative energy timeline and judges faults.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace glbudget::sensors {

enum class ReadingKind {
  energy_j,  // cumulative energy counter in joules (preferred: per-frame energy is a difference)
  power_w,   // instantaneous (or driver-averaged) power in watts
};

enum class ReadStatus {
  ok,           // value is valid (still checked for NaN, sign and plausibility by the Sampler)
  no_new_data,  // nothing new since the previous read (an idle FIFO, an unchanged counter)
  read_error,   // the source vanished or refused (file gone, permission lost, driver error)
  garbage,      // the source answered something that is not a number
};

struct Reading {
  ReadStatus status = ReadStatus::ok;
  ReadingKind kind = ReadingKind::energy_j;
  double value = 0.0;
  std::string detail;  // why, when status is not ok or something was discarded
  // Sources that take several raw samples per read (a meter's FIFO) report here the ones
  // they threw away, so that the Sampler counts them with the other dropped samples.
  std::uint32_t discarded_garbage = 0;
  std::uint32_t discarded_backwards = 0;
};

class Source {
 public:
  virtual ~Source() = default;
  // Short stable name, as in GLBUDGET_SENSOR ("rapl", "cpu", ...). Must have static storage
  // (a string literal): frames carry it to the log thread, which may outlive the sensor.
  virtual std::string_view name() const = 0;
  // What is read, for humans: "package-0 energy_uj (/sys/class/powercap/intel-rapl:0)".
  virtual std::string description() const = 0;
  // True when the figures are modelled rather than measured (the cpu sensor).
  virtual bool is_estimate() const { return false; }
  // Called on the sampling thread only, with the CLOCK_MONOTONIC time of the read.
  virtual Reading read(std::int64_t now_ns) = 0;
  // Sources whose cumulative energy can be computed at any instant, cheaply, without I/O and
  // without failing (the cpu estimate: one clock read) return it here. The PowerSensor then
  // computes each frame's energy exactly at the swap and needs no sampling thread.
  virtual std::optional<double> energy_now_j(std::int64_t /*now_ns*/) const { return std::nullopt; }
};

}  // namespace glbudget::sensors
