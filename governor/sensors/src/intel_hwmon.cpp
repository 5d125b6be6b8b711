// i915 and xe: discrete Intel GPUs publish card energy as hwmon energy1_input (µJ).
// (Integrated Intel GPUs have no hwmon; use rapl:domain=uncore there.)
#include "hwmon_source.hpp"

namespace glbudget::sensors {

OpenResult open_intel_hwmon(const SensorSpec& spec, const SourceEnvironment& env) {
  return open_hwmon(spec, env, spec.kind == "xe" ? "xe" : "i915", {{"energy1_input", ReadingKind::energy_j}});
}

}  // namespace glbudget::sensors
