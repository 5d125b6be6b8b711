#pragma once
#include <initializer_list>
#include <string_view>

#include "sources.hpp"

namespace glbudget::sensors {

struct HwmonAttribute {
  const char* file;  // e.g. "energy1_input" (µJ) or "power1_average" (µW)
  ReadingKind kind;
};

// Opens the spec's `index`-th (default 0) hwmon whose name is `hwmon_name`, reading the first
// attribute of `preference` that answers with a number. `hwmon_name` is also the source's
// name, so it must be a string literal (see Source::name()).
OpenResult open_hwmon(const SensorSpec& spec, const SourceEnvironment& env, std::string_view hwmon_name,
                      std::initializer_list<HwmonAttribute> preference);

}  // namespace glbudget::sensors
