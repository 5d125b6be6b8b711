#pragma once
// Which shader variants (by the log's pass hash) are which quality level of which pass, with
// their per-invocation costs. The shader instrumentation measures the costs; this JSON form
// lets a replay of a frame log know configurations without the rest of the shim:
//   {"passes": [{"name": "shading",
//                "levels": [{"hash": "0123456789abcdef", "ins_v": 24, "ins_f": 180, "tex_f": 6},
//                           ...]},
//               {"name": "resolution", "scales": ["shading", ...],
//                "levels": [{"fragment_scale": 1}, {"fragment_scale": 0.64}, ...]},
//               {"name": "reflections",
//                "levels": [{"hashes": ["..."], ...}, ..., {"draws": false}]}, ...]}
// Levels below the best may carry "error_ratio" (their error over the cheapest level's).
// A level may name several programs ("hashes"), none (a render scale), or skip the pass.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/platform_profile.hpp"
#include "glbudget/model/power_model.hpp"

namespace glbudget::model {

struct VariantRef {
  std::size_t pass = 0;  // index in the space
  int level = 0;         // -1: the program serves several levels of its pass
};

struct VariantTable {
  ConfigurationSpace space;
  std::map<std::string, VariantRef> by_hash;
  // What a batch, vertex, fragment, instruction and texel cost in this app's frames, when
  // `glbudget calibrate --app` measured its levels' power too ("platform_costs", the five
  // numbers of a profile's "costs"): the run-time model starts from these rather than the
  // profile's, which came from other apps or none.
  std::optional<PlatformCosts> platform_costs;
  // The power `glbudget calibrate --app` measured at the best configuration (every pass at
  // level 0) and at the cheapest (every pass at its last level), from its "power" section.
  struct MeasuredRange {
    double best_w = 0.0, cheapest_w = 0.0;
  };
  std::optional<MeasuredRange> measured_range;
  // Every configuration of the power run with its measured power (the best, each level alone,
  // the cheapest), in the table's space.
  std::vector<std::pair<Configuration, double>> measured_power_w;
  // k = e_i(l) / e_i(lmax) (paper §6.2), by pass name and level, where `glbudget calibrate
  // --app` probed every level of the pass (a level's "error_ratio", in [0, 1]).
  std::map<std::pair<std::string, int>, double> error_ratios;
};

// Malformed entries: one `glbudget:` line each, and the entry is left out.
std::optional<VariantTable> parse_variant_table(const std::string& json_text, const std::string& source);
std::optional<VariantTable> load_variant_table(const std::string& path);

// "0:2:1:0:0:1", one level per pass of the space in its order; nullopt unless it is one of
// the space's configurations.
std::optional<Configuration> parse_configuration(std::string_view text, const ConfigurationSpace& space);

}  // namespace glbudget::model
