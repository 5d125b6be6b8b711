#pragma once
// The per-machine constants of the power model (paper §5.2): idle and saturated power, and the
// batch, vertex-invocation and fragment-invocation counts per frame that saturate the GPU.
// `glbudget calibrate` measures them once per machine and writes them as JSON.
#include <optional>
#include <string>

namespace glbudget::model {

// Beyond the paper: what a batch, a vertex, a fragment, an instruction and a texel access cost
// on this machine, whatever the pass. A pass at a level with Ins_v, Ins_f, Tex_f (shader
// instrumentation) then starts from
//   k_b = batch,  k_v = vertex + instruction * Ins_v,  k_f = fragment + instruction * Ins_f + texel * Tex_f,
// the paper's reuse (chi = instruction, psi = texel) with a per-invocation cost added. The
// run-time fit starts from these instead of from nothing: a fitting window of a slow camera
// cannot tell one pass's cost from another's (their counts barely change), and without a prior
// the first configuration's coefficients, and every prediction reused from them, are a guess.
// Fitted from recorded logs by `glbudget costs` (analysis/cost_fit.hpp).
struct PlatformCosts {
  double batch = 0.0;
  double vertex = 0.0;
  double fragment = 0.0;
  double instruction = 0.0;  // chi
  double texel = 0.0;        // psi
};

struct PlatformProfile {
  double p_min_w = 0.0;                 // P_m: power of an empty frame
  double p_max_w = 1.0;                 // P_M: power of a saturated GPU
  double saturation_batches = 1.0e4;    // B
  double saturation_vertices = 1.0e8;   // V
  double saturation_fragments = 1.0e9;  // F
  std::optional<PlatformCosts> costs;   // optional "costs" object

  double range_w() const { return p_max_w - p_min_w; }
};

// Parses a profile such as
//   {"p_min_w": 20, "p_max_w": 65,
//    "saturation": {"batches": 5000, "vertices": 3e7, "fragments": 4e8},
//    "costs": {"batch": 2.1, "vertex": 0.5, "fragment": 1.2, "instruction": 0.02, "texel": 0.3}}
// ("costs" is optional; when present, all five must be numbers >= 0 or it is left out).
// Every missing or invalid field prints one `glbudget:` line on stderr and keeps its default;
// a file that cannot be read or parsed gives std::nullopt (after one such line).
std::optional<PlatformProfile> load_platform_profile(const std::string& path);
PlatformProfile parse_platform_profile(const std::string& json_text, const std::string& source);
std::string platform_profile_to_json(const PlatformProfile& profile);

}  // namespace glbudget::model
