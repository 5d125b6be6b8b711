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
}  // namespace

std::string default_profile_path(const std::string& sensor) {
  std::string base;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    base = xdg;
  else if (const char* home = std::getenv("HOME"); home && *home)
    base = std::string(home) + "/.cache";
  if (base.empty()) return {};
  return base + "/glbudget/" + sensor_kind(sensor) + ".json";
}

}  // namespace glbudget::sensors
