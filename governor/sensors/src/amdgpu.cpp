// amdgpu: the AMD GPU's hwmon. Energy where the driver exposes it (energy1_input, µJ),
// otherwise power1_average, otherwise power1_input (both µW; recent GPUs only have the latter).
#include "hwmon_source.hpp"

namespace glbudget::sensors {

OpenResult open_amdgpu(const SensorSpec& spec, const SourceEnvironment& env) {
  return open_hwmon(spec, env, "amdgpu",
                    {{"energy1_input", ReadingKind::energy_j},
                     {"power1_average", ReadingKind::power_w},
                     {"power1_input", ReadingKind::power_w}});
}

}  // namespace glbudget::sensors
