#include "glbudget/sensors/power_log.hpp"

#include <cstdio>

namespace glbudget::sensors {

int format_power_fields(const FrameEnergy& frame, char* out, int size) {
  const int name_length = static_cast<int>(frame.sensor.size());
  const char* label = frame.estimate ? "~estimate" : "";
  if (!frame.valid)
    return std::snprintf(out, static_cast<std::size_t>(size), ",,%.*s%s", name_length, frame.sensor.data(), label);
  // %.9g keeps nanojoule resolution on per-frame energies of a few joules.
  return std::snprintf(out, static_cast<std::size_t>(size), "%.6g,%.9g,%.*s%s", frame.mean_power_w, frame.energy_j,
                       name_length, frame.sensor.data(), label);
}

}  // namespace glbudget::sensors
