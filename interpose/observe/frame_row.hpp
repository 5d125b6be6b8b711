// One row of the frame log: one frame of one context, one pass.
#pragma once
#include <cstdint>
#include <string>

#include "glbudget/sensors/sensor.hpp"

namespace glbudget {

using PassId = uint64_t;
constexpr PassId kFixedFunctionPass = 0;  // draws with no program bound

struct FrameRow {
  uint64_t frame = 0;
  int64_t time_ns = 0;  // CLOCK_MONOTONIC at the frame's swap
  int context = 0;      // order in which the process first made the context current
  PassId pass = kFixedFunctionPass;
  uint64_t batches = 0;
  // Driver-reported figures; -1 when not measured (no query support, the app held the
  // query target, or the result was lost with its context).
  int64_t vertices = -1;
  int64_t fragments = -1;
  int64_t primitives = -1;
  int64_t gpu_ns = -1;
  // The process's energy over the interval since the previous swap (of any context): power
  // is a whole-process (whole-GPU) quantity. Invalid (empty fields) without a sensor.
  sensors::FrameEnergy energy;
  // The levels that drew the frame ("0:2:1"), when a manifest or GLBUDGET_FORCE is in force.
  std::string configuration;
  // Filled in by the governor (apply/governing.hpp): its prediction of the frame's power, the
  // budget in watts, the estimated error of the configuration it chose, what it did.
  double predicted_w = __builtin_nan("");
  double budget_w = __builtin_nan("");
  double est_error = __builtin_nan("");
  const char* decision = nullptr;
  // A quality-probe frame (apply/probes.hpp): drawn a second time for the probes, so its counts
  // and power are not the frame's own. probe_error: 1 - SSIM of what was shown against the
  // best configuration, measured on this frame (NaN: not measured).
  bool probe = false;
  int probe_sweep_streams = 0;  // a probe frame that measured every pass at once: its streams
  double probe_error = __builtin_nan("");
  // What the probe streams measured: "levels=error" ("0:0:2=0.031250"), the error of a
  // stream's image against the best configuration's; ';' between streams (all but s0's).
  std::string probe_streams;
};

}  // namespace glbudget
