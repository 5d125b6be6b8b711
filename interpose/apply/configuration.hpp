// Which configuration each frame draws: the variant manifest (GLBUDGET_CONFIG, else
// $XDG_CONFIG_HOME/glbudget/<exe>.toml) with the render-scale pass first, and the level of each
// of its passes. GLBUDGET_FORCE fixes the levels from the first frame; a list of configurations
// separated by ';' is stepped through every GLBUDGET_FORCE_EVERY frames (a test's handle on
// switching at run time). A context takes a new configuration at its swap, so a frame is never
// drawn half in one configuration and half in another.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "glbudget/manifest/manifest.hpp"

namespace glbudget {

// Up to this many passes are carried per frame record.
constexpr int kMaxPasses = 16;

struct Levels {
  int count = 0;
  int8_t level[kMaxPasses] = {};
  bool operator==(const Levels& o) const {
    if (count != o.count) return false;
    for (int i = 0; i < count; ++i)
      if (level[i] != o.level[i]) return false;
    return true;
  }
  int operator[](int pass) const { return pass < count ? level[pass] : 0; }
};

// "0:2:1", as in the frame log's configuration column.
std::string format_levels(const Levels& levels);
int format_levels(const Levels& levels, char* out, int size);

// This process's program file name (for the default manifest and variant-table paths).
std::string executable_name();

// The manifest in force (the built-in render-scale pass alone when there is none). Loaded
// once, at the first make-current; problems are reported then.
const manifest::Manifest& active_manifest();
bool manifest_has_programs();    // any pass matches programs
bool manifest_scales_targets();  // any level scales the app's render targets
bool manifest_scales_window();   // any level scales the default framebuffer
// Fragment shaders see the app's pixels in scaled targets (manifest `shader_coordinates`).
bool manifest_app_coordinates();

// The configuration the frame with this number (1-based, per context) draws.
Levels configuration_for_frame(uint64_t frame);
// Whether the configuration can change while the app runs: the governor chooses it (a budget is
// in force), or a GLBUDGET_FORCE list is stepped through (GLBUDGET_FORCE_EVERY).
bool configuration_may_change();

// A pass whose programs were matched at least once (for the report at exit).
void note_pass_matched(int pass);
// One `glbudget:` line per manifest pass that never matched a program in this process.
void report_unmatched_passes();

}  // namespace glbudget
