// Fuzz target: the power sensor spec (GLBUDGET_SENSOR, `glbudget run --sensor`):
// "auto", "rapl", "amdgpu:card=1", "file:PATH", ... and its sampling period
// (GLBUDGET_SENSOR_PERIOD_MS, 1..1000). Input: the value, given to both. Only the spec is
// parsed here; opening the sensor it names needs the machine's sysfs.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "glbudget/sensors/registry.hpp"
#include "glbudget/sensors/sensor.hpp"

namespace sensors = glbudget::sensors;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  std::string error;
  const std::optional<sensors::SensorSpec> spec = sensors::parse_sensor_spec(text, error);
  if (!spec && error.empty()) std::abort();  // a rejection says why
  if (spec && spec->kind.empty()) std::abort();
  const auto period = sensors::parse_sampling_period_ms(text);
  if (period && (period->count() < 1 || period->count() > 1000)) std::abort();
  return 0;
}
