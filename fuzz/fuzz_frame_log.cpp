// Fuzz target: the frame-log reader (GLBUDGET_LOG's CSV, read by `glbudget replay`, `costs`,
// `calibrate`). Input: the CSV text.
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "glbudget/analysis/frame_log.hpp"

namespace analysis = glbudget::analysis;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  const std::optional<analysis::FrameLog> log = analysis::read_frame_log(in, "fuzz.csv");
  if (!log) return 0;
  std::size_t passes = 0;
  for (const analysis::LoggedFrame& frame : log->frames) passes += frame.passes.size();
  if (passes + log->rows_skipped != log->rows) std::abort();  // every row is a pass or skipped
  (void)analysis::frames_of_busiest_context(*log);
  return 0;
}
