#include "options.hpp"

#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "scenes/registry.hpp"

namespace demo {
namespace {

void complain(std::string_view flag, std::string_view value, std::string_view expected) {
  std::fprintf(stderr, "demo: ignoring %.*s '%.*s': expected %.*s\n", static_cast<int>(flag.size()), flag.data(),
               static_cast<int>(value.size()), value.data(), static_cast<int>(expected.size()), expected.data());
}

template <typename T>
void number(std::string_view flag, std::string_view text, T& target, T min, T max) {
  T value{};
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value >= min && value <= max)) {
    complain(flag, text, "a number in [" + std::to_string(min) + ", " + std::to_string(max) + "]");
    return;
  }
  target = value;
}

}  // namespace

const char* usage() {
  return "usage: demo [--scene hall|sponza|valley|subway] [--width W] [--height H] [--detail D]\n"
         "            [--shadow-size S] [--frames N] [--start-frame F] [--fps R] [--config r,b,s,h,m,a]\n"
         "            [--dump DIR] [--dump-every K] [--glx] [--stats] [--bench] [--all-configs]\n"
         "  --config   quality level per pass, 0 best .. 2 cheapest: resolution, base shading,\n"
         "             reflections, shadows, metals, antialiasing (default 0,0,0,0,0,0)\n"
         "  --shadow-size  the shadow map's side at the best level (default 2048; levels 1 and 2\n"
         "             halve and quarter it): smaller maps make small test runs cheaper\n"
         "  --stats    print the scene's statistics row (triangles, objects, size, draws per pass)\n"
         "  --bench    print mean frame times of the best and the cheapest configuration\n"
         "  --all-configs  dump the start frame in each of the 729 configurations into --dump\n";
}

Options parse_options(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string_view flag = argv[i];
    bool* const switch_flag = flag == "--glx"                      ? &o.glx
                              : flag == "--stats"                  ? &o.stats
                              : flag == "--bench"                  ? &o.bench
                              : flag == "--all-configs"            ? &o.all_configs
                              : (flag == "--help" || flag == "-h") ? &o.help
                                                                   : nullptr;
    if (switch_flag) {
      *switch_flag = true;
      continue;
    }
    if (i + 1 >= argc) {
      std::fprintf(stderr, "demo: ignoring '%s': unknown or missing its value\n", argv[i]);
      continue;
    }
    const std::string_view value = argv[++i];
    if (flag == "--scene") {
      if (is_scene_name(value))
        o.scene = value;
      else
        complain(flag, value, "hall, sponza, valley or subway");
    } else if (flag == "--width")
      number(flag, value, o.width, 16, 8192);
    else if (flag == "--height")
      number(flag, value, o.height, 16, 8192);
    else if (flag == "--detail")
      number(flag, value, o.detail, 0.001f, 4.0f);
    else if (flag == "--shadow-size")
      number(flag, value, o.shadow_size, 16, 8192);
    else if (flag == "--frames")
      number(flag, value, o.frames, 1L, 1000000L);
    else if (flag == "--start-frame")
      number(flag, value, o.start_frame, 0L, 100000000L);
    else if (flag == "--fps")
      number(flag, value, o.fps, 1.0, 1000.0);
    else if (flag == "--dump-every")
      number(flag, value, o.dump_every, 1L, 1000000L);
    else if (flag == "--dump")
      o.dump_dir = value;
    else if (flag == "--config") {
      if (auto config = parse_config(value))
        o.config = *config;
      else
        complain(flag, value, "six levels 0..2 separated by commas, e.g. 0,1,2,0,0,1");
    } else {
      std::fprintf(stderr, "demo: ignoring unknown option '%s'\n", argv[i - 1]);
      --i;  // its "value" may be the next option
    }
  }
  return o;
}

}  // namespace demo
