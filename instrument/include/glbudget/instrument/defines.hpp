#pragma once
// Setting preprocessor macros in an app's GLSL from outside: a variant manifest's `defines`.
// A macro the source already defines (an object-like `#define NAME ...` line) is redefined in
// place, so the variant's source is the one the app would have built with that value; any
// other is added after `#version` and the `#extension` lines that follow it, with a `#line`
// so the app's lines keep their numbers in the driver's messages.
#include <string>
#include <utility>
#include <vector>

namespace glbudget::instrument {

using Defines = std::vector<std::pair<std::string, std::string>>;

std::string set_defines(const std::string& source, const Defines& defines);

}  // namespace glbudget::instrument
