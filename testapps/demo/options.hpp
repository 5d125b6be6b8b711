// Command line of the demo. Bad values are reported on stderr ("demo: ...") and replaced
// by their defaults; unknown arguments likewise are reported and ignored.
#pragma once
#include <string>

#include "config.hpp"

namespace demo {

struct Options {
  std::string scene = "hall";
  int width = 640, height = 360;
  float detail = 1.0f;               // scales every object's triangle count
  int shadow_size = kShadowMapSize;  // the shadow map's side at the best level
  long frames = 60;                  // frames to render
  long start_frame = 0;              // first frame number (time = frame / fps)
  double fps = 30.0;
  Config config = Config::best();
  std::string dump_dir;      // empty: no images
  long dump_every = 1;       // dump frames start, start + k, start + 2k, ...
  bool glx = false;          // GLX window under X instead of EGL surfaceless
  bool stats = false;        // print the statistics table row and exit
  bool bench = false;        // time best and cheapest configurations and exit
  bool all_configs = false;  // dump the start frame in each of the 729 configurations and exit
  bool help = false;
};

Options parse_options(int argc, char** argv);
const char* usage();

}  // namespace demo
