#pragma once
// Where glbudget keeps what it measured: the platform profile of a sensor (`glbudget
// calibrate`) and an app's variant table (`glbudget calibrate --app`), read by `glbudget run`
// and the shim's governor.
#include <string>

namespace glbudget::sensors {

// $XDG_CACHE_HOME/glbudget/<sensor kind>.json (~/.cache when unset): the kind without its
// options ("cpu:idle=5" -> cpu.json), and for "auto" (or empty) the kind auto picks on this
// machine. Empty when neither variable is set.
std::string default_profile_path(const std::string& sensor);

// $XDG_CACHE_HOME/glbudget/<executable>.variants.json (~/.cache when unset): an app's measured
// variant table, by its program's file name. Empty when neither variable is set or no name.
std::string default_variant_table_path(const std::string& executable);

}  // namespace glbudget::sensors
