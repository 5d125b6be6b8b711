#include "glbudget/model/variant_table.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace glbudget::model {
namespace {

using nlohmann::json;

double cost_field(const json& level, const char* key, const std::string& where) {
  const auto it = level.find(key);
  if (it == level.end()) return 0.0;  // e.g. no texel accesses
  if (!it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() < 0.0) {
    std::cerr << "glbudget: " << where << ": \"" << key << "\" must be a number >= 0, using 0\n";
    return 0.0;
  }
  return it->get<double>();
}

// The hashes of a level: "hash": "..." or "hashes": ["...", ...] (several programs drawing
// one pass at one level, e.g. a skinned and a static variant of the same shading).
std::vector<std::string> level_hashes(const json& level, const std::string& where) {
  std::vector<std::string> hashes;
  if (const auto it = level.find("hash"); it != level.end()) {
    if (it->is_string())
      hashes.push_back(it->get<std::string>());
    else
      std::cerr << "glbudget: " << where << ": \"hash\" must be a string; ignored\n";
  }
  if (const auto it = level.find("hashes"); it != level.end()) {
    if (!it->is_array()) {
      std::cerr << "glbudget: " << where << ": \"hashes\" must be an array of strings; ignored\n";
    } else {
      for (const json& hash : *it) {
        if (hash.is_string())
          hashes.push_back(hash.get<std::string>());
        else
          std::cerr << "glbudget: " << where << ": a non-string entry in \"hashes\"; ignored\n";
      }
    }
  }
  return hashes;
}

// "power": {"configurations": [{"configuration": "0:0", "power_w": ...}, ...]}: the entries
// that name a configuration of the space with a positive power (others are left out silently:
// an older table, a run cut short).
std::vector<std::pair<Configuration, double>> measured_powers(const json& document, const ConfigurationSpace& space) {
  std::vector<std::pair<Configuration, double>> out;
  const auto power = document.find("power");
  if (power == document.end() || !power->is_object()) return out;
  const auto list = power->find("configurations");
  if (list == power->end() || !list->is_array() || space.pass_count() == 0) return out;
  for (const json& entry : *list) {
    if (!entry.is_object()) continue;
    const auto name = entry.find("configuration"), watts = entry.find("power_w");
    if (name == entry.end() || !name->is_string() || watts == entry.end() || !watts->is_number()) continue;
    const double w = watts->get<double>();
    const std::optional<Configuration> c = parse_configuration(name->get<std::string>(), space);
    if (c && std::isfinite(w) && w > 0.0) out.emplace_back(*c, w);
  }
  return out;
}

// Best (every pass at level 0) and cheapest (every pass at its last level), when both were measured.
std::optional<VariantTable::MeasuredRange> measured_range(std::span<const std::pair<Configuration, double>> powers,
                                                          const ConfigurationSpace& space) {
  const Configuration best(space.pass_count(), 0), cheapest = space.cheapest();
  std::optional<double> best_w, cheapest_w;
  for (const auto& [c, w] : powers) {
    if (c == best) best_w = w;
    if (c == cheapest) cheapest_w = w;
  }
  if (!best_w || !cheapest_w) return std::nullopt;
  return VariantTable::MeasuredRange{*best_w, *cheapest_w};
}

}  // namespace

std::optional<VariantTable> parse_variant_table(const std::string& json_text, const std::string& source) {
  const json document = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (!document.is_object() || !document.contains("passes") || !document["passes"].is_array()) {
    std::cerr << "glbudget: " << source << ": expected {\"passes\": [...]}\n";
    return std::nullopt;
  }
  std::vector<PassVariants> passes;
  std::map<std::string, VariantRef> by_hash;
  std::map<std::pair<std::string, int>, double> error_ratios;
  for (const json& pass : document["passes"]) {
    if (!pass.is_object() || !pass.contains("name") || !pass["name"].is_string() || !pass.contains("levels") ||
        !pass["levels"].is_array() || pass["levels"].empty()) {
      std::cerr << "glbudget: " << source << ": a pass needs a \"name\" and non-empty \"levels\"; skipped\n";
      continue;
    }
    PassVariants variants{pass["name"].get<std::string>(), {}, {}};
    const std::string where = source + ": pass " + variants.pass;
    if (const auto it = pass.find("scales"); it != pass.end()) {
      if (it->is_array() && std::all_of(it->begin(), it->end(), [](const json& j) { return j.is_string(); })) {
        for (const json& name : *it) variants.scales.push_back(name.get<std::string>());
      } else {
        std::cerr << "glbudget: " << where << ": \"scales\" must be an array of pass names; ignored\n";
      }
    }
    for (const json& level : pass["levels"]) {
      if (!level.is_object()) {
        std::cerr << "glbudget: " << where << ": a level must be an object; skipped\n";
        continue;
      }
      const int index = static_cast<int>(variants.levels.size());
      for (const std::string& hash : level_hashes(level, where)) {
        const VariantRef ref{passes.size(), index};
        const auto [it, inserted] = by_hash.try_emplace(hash, ref);
        // A program shared by several levels (they differ in a uniform or in the
        // render-target size) names the pass but not the level.
        if (!inserted && it->second.pass == ref.pass && it->second.level != index) it->second.level = -1;
      }
      VariantCost cost{cost_field(level, "ins_v", where), cost_field(level, "ins_f", where),
                       cost_field(level, "tex_f", where)};
      if (level.contains("fragment_scale")) cost.fragment_scale = cost_field(level, "fragment_scale", where);
      if (const auto it = level.find("draws"); it != level.end()) {
        if (it->is_boolean())
          cost.draws = it->get<bool>();
        else
          std::cerr << "glbudget: " << where << ": \"draws\" must be true or false; using true\n";
      }
      if (const auto it = level.find("error_ratio"); it != level.end()) {
        if (it->is_number() && it->get<double>() >= 0.0 && it->get<double>() <= 1.0)
          error_ratios[{variants.pass, index}] = it->get<double>();
        else
          std::cerr << "glbudget: " << where << ": \"error_ratio\" must be a number in [0, 1]; ignored\n";
      }
      variants.levels.push_back(cost);
    }
    if (!variants.levels.empty()) passes.push_back(std::move(variants));
  }
  VariantTable table{ConfigurationSpace(std::move(passes)), std::move(by_hash), std::nullopt, std::nullopt, {}, {}};
  if (const auto it = document.find("platform_costs"); it != document.end()) {
    PlatformCosts costs;
    bool ok = it->is_object();
    for (auto [key, field] : {std::pair{"batch", &costs.batch},
                              {"vertex", &costs.vertex},
                              {"fragment", &costs.fragment},
                              {"instruction", &costs.instruction},
                              {"texel", &costs.texel}}) {
      const auto value = ok ? it->find(key) : it->end();
      ok = ok && value != it->end() && value->is_number() && std::isfinite(value->get<double>()) &&
           value->get<double>() >= 0.0;
      if (ok) *field = value->get<double>();
    }
    if (ok)
      table.platform_costs = costs;
    else
      std::cerr << "glbudget: " << source
                << ": \"platform_costs\" needs batch, vertex, fragment, instruction "
                   "and texel, numbers >= 0; ignored\n";
  }
  table.measured_power_w = measured_powers(document, table.space);
  table.measured_range = measured_range(table.measured_power_w, table.space);
  table.error_ratios = std::move(error_ratios);
  return table;
}

std::optional<Configuration> parse_configuration(std::string_view text, const ConfigurationSpace& space) {
  Configuration configuration;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t colon = std::min(text.find(':', start), text.size());
    const std::string_view field = text.substr(start, colon - start);
    int level = -1;
    const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), level);
    if (field.empty() || error != std::errc{} || end != field.data() + field.size()) return std::nullopt;
    configuration.push_back(level);
    start = colon + 1;
  }
  if (!space.contains(configuration)) return std::nullopt;
  return configuration;
}

std::optional<VariantTable> load_variant_table(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << "glbudget: cannot read variant table " << path << "\n";
    return std::nullopt;
  }
  std::stringstream text;
  text << in.rdbuf();
  return parse_variant_table(text.str(), path);
}

}  // namespace glbudget::model
