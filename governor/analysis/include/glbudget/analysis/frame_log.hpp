#pragma once
// Reader for the shim's per-frame CSV log (GLBUDGET_LOG):
//   frame,time_ns,context,pass,batches,vertices,fragments,primitives,gpu_ns[,power_w,energy_j,sensor]
// one row per frame and pass, optionally with a `configuration` column. Columns are found by header name, so reordered
// or additional columns are fine; an empty field means "not measured" and reads as NaN.
#include <cstddef>
#include <cstdint>
#include <iosfwd>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "glbudget/model/power_model.hpp"

namespace glbudget::analysis {

struct LoggedPass {
  std::string pass;                                              // 16-hex-digit source hash, or "fixed-function"
  model::PassCounts counts;                                      // NaN where not measured
  double primitives = std::numeric_limits<double>::quiet_NaN();  // NaN where not measured
  double gpu_ns = std::numeric_limits<double>::quiet_NaN();
};

struct LoggedFrame {
  std::uint64_t frame = 0;
  double time_ns = std::numeric_limits<double>::quiet_NaN();
  std::string context;
  std::vector<LoggedPass> passes;
  // NaN when the log has no power column or the sensor gave nothing.
  double power_w = std::numeric_limits<double>::quiet_NaN();
  double energy_j = std::numeric_limits<double>::quiet_NaN();
  std::string sensor;
  // The `configuration` column ("0:2:1:..."), where the writer knew which it drew.
  std::string configuration;
  // The `probe_streams` column of a quality-probe frame ("0:0:2=0.031250;..."), where measured.
  std::string probe_streams;
};

struct FrameLog {
  std::vector<LoggedFrame> frames;  // in order of first appearance
  std::size_t rows = 0;
  std::size_t rows_skipped = 0;  // malformed rows (reported once on stderr)
};

// Malformed rows are skipped; a missing required column (frame, pass, batches, vertices,
// fragments) makes the whole log unreadable: one `glbudget:` line each way.
std::optional<FrameLog> read_frame_log(std::istream& in, const std::string& source);
std::optional<FrameLog> read_frame_log_file(const std::string& path);

// The frames of the context that logged the most frames (a replay follows one context).
std::vector<LoggedFrame> frames_of_busiest_context(const FrameLog& log);

}  // namespace glbudget::analysis
