#pragma once
// Naming, opening and probing sensors.
//
// GLBUDGET_SENSOR syntax:   KIND[:key=value[,key=value...]]   or   file:PATH
//   auto                      the first available of: nvml, amdgpu, xe, i915, rapl, cpu
//   nvml[:device=N]           NVIDIA, libnvidia-ml loaded at run time
//   amdgpu[:index=N]          AMD hwmon: energy1_input, else power1_average, else power1_input
//   rapl[:domain=D]           powercap energy_uj; D = package (default, all sockets), uncore
//                             (integrated GPU), core, dram or psys
//   i915[:index=N], xe[:index=N]  Intel GPU hwmon energy1_input
//   cpu[:idle=W,max=W,cores=N]    estimate from this process's CPU time (software rendering):
//                             P = idle + (max - idle) * u, u = CPU time / (wall time * cores);
//                             defaults idle=10, max=45, cores = CPUs this process may run on;
//                             computed exactly at each swap (no sampling thread)
//   file:PATH                 an external meter appending "timestamp,watts" lines (file or FIFO)
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "glbudget/sensors/source.hpp"

namespace glbudget::sensors {

struct SensorSpec {
  std::string kind;                           // "auto", "rapl", "file", ...
  std::map<std::string, std::string> params;  // key=value options
  std::string path;                           // file:PATH only
};

// Empty result and a message in `error` for text that is not a sensor spec.
std::optional<SensorSpec> parse_sensor_spec(std::string_view text, std::string& error);

struct SourceEnvironment {
  std::filesystem::path sysfs_root = "/sys";
  std::string nvml_library = "libnvidia-ml.so.1";
  // GLBUDGET_SYSFS_ROOT and GLBUDGET_NVML_LIBRARY override the defaults (tests, odd installs).
  static SourceEnvironment from_process_environment();
};

struct OpenResult {
  std::unique_ptr<Source> source;  // null when unavailable
  std::string why_not;             // then: one human sentence saying why
};

OpenResult open_source(const SensorSpec& spec, const SourceEnvironment& env);

// The kinds "auto" tries, best first (GPU counters, then the CPU package, then the estimate).
const std::vector<std::string>& auto_order();

// Every kind in auto_order() with its default parameters, opened or with the reason it is not.
struct ProbeResult {
  std::string kind;
  OpenResult opened;
};
std::vector<ProbeResult> probe_all(const SourceEnvironment& env);

}  // namespace glbudget::sensors
