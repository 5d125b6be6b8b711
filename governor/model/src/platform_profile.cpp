#include "glbudget/model/platform_profile.hpp"

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <utility>

#include <nlohmann/json.hpp>

namespace glbudget::model {
namespace {

using nlohmann::json;

// Reads `object[key]` into `out` when it is a finite number accepted by `valid`; otherwise
// reports it and leaves the default in place.
template <typename Valid>
void read_number(const json& object, const char* key, double& out, const std::string& source, Valid valid,
                 const char* requirement) {
  const auto it = object.find(key);
  if (it == object.end()) {
    std::cerr << "glbudget: " << source << ": missing \"" << key << "\", using " << out << "\n";
    return;
  }
  if (!it->is_number() || !std::isfinite(it->get<double>()) || !valid(it->get<double>())) {
    std::cerr << "glbudget: " << source << ": \"" << key << "\" must be " << requirement << ", using " << out << "\n";
    return;
  }
  out = it->get<double>();
}

// The optional "costs" object: all or nothing, since a prior with one cost silently at 0
// would make every pass look free of it.
void read_costs(const json& document, PlatformProfile& profile, const std::string& source) {
  const auto costs = document.find("costs");
  if (costs == document.end()) return;
  if (!costs->is_object()) {
    std::cerr << "glbudget: " << source << ": \"costs\" must be an object, ignoring it\n";
    return;
  }
  PlatformCosts parsed;
  const std::pair<const char*, double*> fields[] = {{"batch", &parsed.batch},
                                                    {"vertex", &parsed.vertex},
                                                    {"fragment", &parsed.fragment},
                                                    {"instruction", &parsed.instruction},
                                                    {"texel", &parsed.texel}};
  for (const auto& [key, out] : fields) {
    const auto it = costs->find(key);
    if (it == costs->end() || !it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() < 0.0) {
      std::cerr << "glbudget: " << source << ": \"costs\" needs \"" << key
                << "\" as a number >= 0, ignoring the costs\n";
      return;
    }
    *out = it->get<double>();
  }
  profile.costs = parsed;
}

}  // namespace

PlatformProfile parse_platform_profile(const std::string& json_text, const std::string& source) {
  PlatformProfile profile;
  const json document = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
  if (!document.is_object()) {
    std::cerr << "glbudget: " << source << ": not a JSON object, using the default profile\n";
    return profile;
  }
  const auto non_negative = [](double v) { return v >= 0.0; };
  const auto positive = [](double v) { return v > 0.0; };
  read_number(document, "p_min_w", profile.p_min_w, source, non_negative, "a number >= 0");
  read_number(document, "p_max_w", profile.p_max_w, source, non_negative, "a number >= 0");
  if (profile.p_max_w < profile.p_min_w) {
    std::cerr << "glbudget: " << source << ": p_max_w < p_min_w, treating both as " << profile.p_min_w << " W\n";
    profile.p_max_w = profile.p_min_w;
  }
  const auto saturation = document.find("saturation");
  if (saturation == document.end() || !saturation->is_object()) {
    std::cerr << "glbudget: " << source << ": missing \"saturation\" object, using defaults\n";
    return profile;
  }
  read_number(*saturation, "batches", profile.saturation_batches, source, positive, "a number > 0");
  read_number(*saturation, "vertices", profile.saturation_vertices, source, positive, "a number > 0");
  read_number(*saturation, "fragments", profile.saturation_fragments, source, positive, "a number > 0");
  read_costs(document, profile, source);
  return profile;
}

std::optional<PlatformProfile> load_platform_profile(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << "glbudget: cannot read platform profile " << path << "\n";
    return std::nullopt;
  }
  std::stringstream text;
  text << in.rdbuf();
  if (!json::accept(text.str())) {
    std::cerr << "glbudget: " << path << ": not valid JSON\n";
    return std::nullopt;
  }
  return parse_platform_profile(text.str(), path);
}

std::string platform_profile_to_json(const PlatformProfile& profile) {
  json document = {
      {"p_min_w", profile.p_min_w},
      {"p_max_w", profile.p_max_w},
      {"saturation",
       {{"batches", profile.saturation_batches},
        {"vertices", profile.saturation_vertices},
        {"fragments", profile.saturation_fragments}}},
  };
  if (profile.costs) {
    document["costs"] = {{"batch", profile.costs->batch},
                         {"vertex", profile.costs->vertex},
                         {"fragment", profile.costs->fragment},
                         {"instruction", profile.costs->instruction},
                         {"texel", profile.costs->texel}};
  }
  return document.dump(2);
}

}  // namespace glbudget::model
