#pragma once
// Where glbudget's own files are: the shim, its helper programs, the platform profile.
#include <string>

namespace glbudget::cli {

// The shim: $GLBUDGET_SHIM, else beside this program in the build tree (cli/../interpose), or
// where `cmake --install` puts it (bin/../lib/<multiarch>/glbudget/). Empty when not found.
std::string find_shim();

// LD_PRELOAD for an app run with the shim: the shim, then what the user preloads (`inherited`,
// when not empty). In a sanitizer build of glbudget, whose shim is sanitized too, the
// sanitizer's runtime comes first: an unsanitized app must load it ahead of the shim.
std::string preload_with_shim(const std::string& shim, const char* inherited);

// A helper program built with glbudget: $<env_variable>, else in the build tree
// (cli/../<build_dir>/<name>), else bin/../lib/glbudget/<name>. Empty when not found.
std::string find_helper(const char* name, const char* build_dir, const char* env_variable);

// $XDG_CACHE_HOME/glbudget/<sensor kind>.json (~/.cache when unset), where `glbudget
// calibrate` writes the profile and `glbudget run` looks for it: the kind without its options
// ("cpu:idle=5" -> cpu.json), and for "auto" (or empty) the kind auto picks on this machine.
// Empty when neither variable is set.
std::string default_profile(const std::string& sensor);

}  // namespace glbudget::cli
