// Fuzz target: the power sensor spec (GLBUDGET_SENSOR, `glbudget run --sensor`):
// "auto", "rapl", "amdgpu:card=1", "file:PATH", ... Input: the value. Only the spec is parsed
// here; opening the sensor it names needs the machine's sysfs.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "glbudget/sensors/registry.hpp"

namespace sensors = glbudget::sensors;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string error;
  const std::optional<sensors::SensorSpec> spec =
      sensors::parse_sensor_spec(std::string_view(reinterpret_cast<const char*>(data), size), error);
  if (!spec && error.empty()) std::abort();  // a rejection says why
  if (spec && spec->kind.empty()) std::abort();
  return 0;
}
