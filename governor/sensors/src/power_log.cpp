#include "glbudget/sensors/power_log.hpp"

#include <cstdio>

namespace glbudget::sensors {

void append_power_fields(std::string& row, const FrameEnergy& frame) {
  if (frame.valid) {
    char numbers[64];
    // %.9g keeps nanojoule resolution on per-frame energies of a few joules.
    std::snprintf(numbers, sizeof numbers, "%.6g,%.9g", frame.mean_power_w, frame.energy_j);
    row += numbers;
  } else {
    row += ',';
  }
  row += ',';
  row += frame.sensor;
  if (frame.estimate) row += "~estimate";
}

}  // namespace glbudget::sensors
