#include "glbudget/sensors/profile_path.hpp"

#include <cstdlib>

#include "glbudget/sensors/registry.hpp"

namespace glbudget::sensors {

namespace {
// The kind a sensor spec names; "auto" resolved as the shim resolves it.
std::string sensor_kind(const std::string& sensor) {
  const std::string kind = sensor.empty() ? "auto" : sensor.substr(0, sensor.find(':'));
  if (kind != "auto") return kind;
  std::string error;
  const auto spec = parse_sensor_spec("auto", error);
  if (!spec) return kind;
  const OpenResult opened = open_source(*spec, SourceEnvironment::from_process_environment());
  return opened.source ? std::string(opened.source->name()) : kind;
}

// $XDG_CACHE_HOME/glbudget (~/.cache/glbudget when unset); empty when neither is set.
std::string cache_directory() {
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/glbudget";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/glbudget";
  return {};
}
}  // namespace

std::string default_profile_path(const std::string& sensor) {
  const std::string dir = cache_directory();
  return dir.empty() ? std::string() : dir + "/" + sensor_kind(sensor) + ".json";
}

std::string default_variant_table_path(const std::string& executable) {
  const std::string dir = cache_directory();
  return dir.empty() || executable.empty() ? std::string() : dir + "/" + executable + ".variants.json";
}

}  // namespace glbudget::sensors
