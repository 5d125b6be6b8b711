// Command line of calibrate_load. Every option is checked: the program is driven by
// `glbudget calibrate`, which would rather hear of a bad value than measure a wrong load.
#pragma once
#include <cstdint>
#include <optional>

namespace calibrate_load {

struct LoadOptions {
  std::int64_t batches = 1;    // draw calls per frame; 0 draws nothing at all
  std::int64_t vertices = 3;   // vertices per batch (rounded up to whole triangles)
  std::int64_t fragments = 0;  // fragments per frame (full-screen layers, the last one partial)
  double fps = 0.0;            // pacing; 0 = as fast as possible
  double seconds = 1.0;        // how long to draw (each step of a sweep)
  std::int64_t frames = 0;     // at most this many frames a step; 0 = no limit
  // A sweep: `steps` steps, the swept count multiplied by `factor` from one to the next.
  enum class Sweep { none, batches, vertices, fragments } sweep = Sweep::none;
  double factor = 2.0;
  int steps = 1;
  int stop_when_late = 0;  // end the sweep after this many late steps in a row; 0 = never
  int width = 256;
  int height = 256;
  bool help = false;
};

const char* usage();
// Nothing (after one message on stderr) when an option is unknown or a value is out of range.
std::optional<LoadOptions> parse_options(int argc, char** argv);

}  // namespace calibrate_load
