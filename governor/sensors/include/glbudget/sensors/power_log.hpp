#pragma once
// The power columns of the per-frame CSV log (GLBUDGET_LOG), written in one place so that
// the shim that writes them and the tools that read them agree.
#include <string>
#include <string_view>

#include "glbudget/sensors/sensor.hpp"

namespace glbudget::sensors {

inline constexpr std::string_view power_log_columns = "power_w,energy_j,sensor";

// Appends "power_w,energy_j,sensor" (no leading comma). Power and energy are empty when the
// frame has no valid measurement. The sensor field is the source's name, with "~estimate"
// appended for modelled figures (e.g. "cpu~estimate"), so no report can mistake them for
// measurements.
void append_power_fields(std::string& row, const FrameEnergy& frame);

}  // namespace glbudget::sensors
