#include "load_options.hpp"

#include <charconv>
#include <cstdio>
#include <string>
#include <string_view>

namespace calibrate_load {
namespace {

template <typename T>
bool number(std::string_view flag, std::string_view text, T& target, T min, T max) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value >= min && value <= max)) {
    std::fprintf(stderr, "calibrate_load: %.*s '%.*s': expected a number in [%s, %s]\n", static_cast<int>(flag.size()),
                 flag.data(), static_cast<int>(text.size()), text.data(), std::to_string(min).c_str(),
                 std::to_string(max).c_str());
    return false;
  }
  target = value;
  return true;
}

}  // namespace

const char* usage() {
  return "usage: calibrate_load [--batches N] [--vertices V] [--fragments F] [--fps R] [--seconds S]\n"
         "                      [--frames N] [--width W] [--height H]\n"
         "                      [--sweep batches|vertices|fragments --steps K [--factor X] [--stop-when-late L]]\n"
         "Draws frames of N draw calls of V vertices each (degenerate triangles: vertex work only)\n"
         "plus F fragments (additively blended full-screen layers, drawn by the first call) for S\n"
         "seconds (at least one frame, at most --frames), paced to R frames per second (0: unpaced).\n"
         "--batches 0 draws nothing. A sweep runs K such steps, multiplying the swept count by X\n"
         "(default 2) each time, and ends early after L steps in a row ran at under half of R.\n"
         "Each step ends with its work finished and prints one line on stdout:\n"
         "  step I batches N vertices V fragments F start_ns T0 end_ns T1 frames K late 0|1 [interrupted]\n"
         "(CLOCK_MONOTONIC; the step's frames are those presented after T0 up to T1).\n";
}

std::optional<LoadOptions> parse_options(int argc, char** argv) {
  LoadOptions o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view flag = argv[i];
    if (flag == "--help" || flag == "-h") {
      o.help = true;
      continue;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "calibrate_load: %s: unknown option or missing value\n%s", argv[i], usage());
      return std::nullopt;
    }
    const std::string_view value = argv[++i];
    bool ok = false;
    if (flag == "--batches")
      ok = number(flag, value, o.batches, std::int64_t{0}, std::int64_t{10'000'000});
    else if (flag == "--vertices")
      ok = number(flag, value, o.vertices, std::int64_t{1}, std::int64_t{1'000'000'000});
    else if (flag == "--fragments")
      ok = number(flag, value, o.fragments, std::int64_t{0}, std::int64_t{100'000'000'000});
    else if (flag == "--fps")
      ok = number(flag, value, o.fps, 0.0, 10000.0);
    else if (flag == "--seconds")
      ok = number(flag, value, o.seconds, 0.0, 86400.0);
    else if (flag == "--frames")
      ok = number(flag, value, o.frames, std::int64_t{0}, std::int64_t{1'000'000'000});
    else if (flag == "--width")
      ok = number(flag, value, o.width, 1, 8192);
    else if (flag == "--height")
      ok = number(flag, value, o.height, 1, 8192);
    else if (flag == "--factor")
      ok = number(flag, value, o.factor, 1.0, 1000.0);
    else if (flag == "--steps")
      ok = number(flag, value, o.steps, 1, 10000);
    else if (flag == "--stop-when-late")
      ok = number(flag, value, o.stop_when_late, 0, 10000);
    else if (flag == "--sweep") {
      using Sweep = LoadOptions::Sweep;
      o.sweep = value == "batches"     ? Sweep::batches
                : value == "vertices"  ? Sweep::vertices
                : value == "fragments" ? Sweep::fragments
                                       : Sweep::none;
      ok = o.sweep != Sweep::none;
      if (!ok) std::fprintf(stderr, "calibrate_load: --sweep '%s': expected batches, vertices or fragments\n", argv[i]);
    } else
      std::fprintf(stderr, "calibrate_load: unknown option %s\n%s", argv[i - 1], usage());
    if (!ok) return std::nullopt;
  }
  return o;
}

}  // namespace calibrate_load
