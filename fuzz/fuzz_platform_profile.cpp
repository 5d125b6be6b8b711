// Fuzz target: the platform-profile reader (GLBUDGET_PROFILE's JSON, written by `glbudget
// calibrate`). Input: the JSON text; parsed, then written and read back.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "glbudget/model/platform_profile.hpp"

namespace model = glbudget::model;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const model::PlatformProfile profile = model::parse_platform_profile(text, "fuzz.json");
  // What the model relies on: finite, p_min <= p_max, saturation counts > 0.
  if (!(profile.p_min_w >= 0.0 && profile.p_min_w <= profile.p_max_w && std::isfinite(profile.p_max_w))) std::abort();
  if (!(profile.saturation_batches > 0.0 && profile.saturation_vertices > 0.0 && profile.saturation_fragments > 0.0))
    std::abort();
  const model::PlatformProfile again =
      model::parse_platform_profile(model::platform_profile_to_json(profile), "fuzz.json (written back)");
  if (again.p_min_w != profile.p_min_w || again.p_max_w != profile.p_max_w ||
      again.saturation_fragments != profile.saturation_fragments ||
      again.costs.has_value() != profile.costs.has_value())
    std::abort();
  return 0;
}
