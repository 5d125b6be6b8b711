#pragma once
// Where the platform profile of a sensor lives: what `glbudget calibrate` writes, and what
// `glbudget run` and the shim's governor read.
#include <string>

namespace glbudget::sensors {

// $XDG_CACHE_HOME/glbudget/<sensor kind>.json (~/.cache when unset): the kind without its
// options ("cpu:idle=5" -> cpu.json), and for "auto" (or empty) the kind auto picks on this
// machine. Empty when neither variable is set.
std::string default_profile_path(const std::string& sensor);

}  // namespace glbudget::sensors
