#pragma once
#include <initializer_list>
#include <string>

#include "sources.hpp"

namespace glbudget::sensors {

struct HwmonAttribute {
  const char* file;  // e.g. "energy1_input" (µJ) or "power1_average" (µW)
  ReadingKind kind;
};

// Opens the spec's `index`-th (default 0) hwmon whose name is `hwmon_name`, reading the first
// attribute of `preference` that answers with a number.
OpenResult open_hwmon(const SensorSpec& spec, const SourceEnvironment& env,
                      const std::string& hwmon_name, std::initializer_list<HwmonAttribute> preference);

}  // namespace glbudget::sensors
