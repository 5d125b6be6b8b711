#pragma once
// The per-machine constants of the power model (paper §5.2): idle and saturated power, and the
// batch, vertex-invocation and fragment-invocation counts per frame that saturate the GPU.
// `glbudget calibrate` measures them once per machine and writes them as JSON.
#include <optional>
#include <string>

namespace glbudget::model {

struct PlatformProfile {
    double p_min_w = 0.0;                  // P_m: power of an empty frame
    double p_max_w = 1.0;                  // P_M: power of a saturated GPU
    double saturation_batches = 1.0e4;     // B
    double saturation_vertices = 1.0e8;    // V
    double saturation_fragments = 1.0e9;   // F

    double range_w() const { return p_max_w - p_min_w; }
};

// Parses a profile such as
//   {"p_min_w": 20, "p_max_w": 65,
//    "saturation": {"batches": 5000, "vertices": 3e7, "fragments": 4e8}}
// Every missing or invalid field prints one `glbudget:` line on stderr and keeps its default;
// a file that cannot be read or parsed gives std::nullopt (after one such line).
std::optional<PlatformProfile> load_platform_profile(const std::string& path);
PlatformProfile parse_platform_profile(const std::string& json_text, const std::string& source);
std::string platform_profile_to_json(const PlatformProfile& profile);

}  // namespace glbudget::model
