#pragma once
// The power columns of the per-frame CSV log (GLBUDGET_LOG), written in one place so that
// the shim that writes them and the tools that read them agree.
#include <string_view>

#include "glbudget/sensors/sensor.hpp"

namespace glbudget::sensors {

inline constexpr std::string_view power_log_columns = "power_w,energy_j,sensor";

// Formats "power_w,energy_j,sensor" (no leading comma, no newline) into `out` and returns the
// length snprintf would (truncated if >= size). Power and energy are empty when the frame has
// no valid measurement. The sensor field is the source's name, with "~estimate" appended for
// modelled figures (e.g. "cpu~estimate"), so no report can mistake them for measurements.
int format_power_fields(const FrameEnergy& frame, char* out, int size);

}  // namespace glbudget::sensors
