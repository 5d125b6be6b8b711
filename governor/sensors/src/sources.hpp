#pragma once
// One opener per kind of source; each lives in its own file (rapl.cpp, amdgpu.cpp, ...).
#include "glbudget/sensors/registry.hpp"

namespace glbudget::sensors {

OpenResult open_nvml(const SensorSpec& spec, const SourceEnvironment& env);
OpenResult open_amdgpu(const SensorSpec& spec, const SourceEnvironment& env);
OpenResult open_rapl(const SensorSpec& spec, const SourceEnvironment& env);
OpenResult open_intel_hwmon(const SensorSpec& spec, const SourceEnvironment& env);  // i915, xe
OpenResult open_cpu(const SensorSpec& spec, const SourceEnvironment& env);
OpenResult open_file(const SensorSpec& spec, const SourceEnvironment& env);

// Parameter helpers for openers: they check that only `allowed` keys were given and parse
// values, setting `error` (and returning false) on anything unexpected.
bool only_params(const SensorSpec& spec, std::initializer_list<std::string_view> allowed, std::string& error);
bool param_number(const SensorSpec& spec, const std::string& key, double& value, std::string& error);
bool param_index(const SensorSpec& spec, const std::string& key, unsigned& value, std::string& error);

inline OpenResult unavailable(std::string why) { return OpenResult{nullptr, std::move(why)}; }

}  // namespace glbudget::sensors
