#include "glbudget/sensors/registry.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>

#include "sources.hpp"

namespace glbudget::sensors {

namespace {

using Opener = OpenResult (*)(const SensorSpec&, const SourceEnvironment&);

struct Kind {
  std::string_view name;
  Opener open;
};

// auto_order() is this table's order, without "file" (it needs a path).
constexpr Kind kinds[] = {
    {"nvml", open_nvml}, {"amdgpu", open_amdgpu}, {"xe", open_intel_hwmon}, {"i915", open_intel_hwmon},
    {"rapl", open_rapl}, {"cpu", open_cpu},       {"file", open_file},
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

}  // namespace

std::optional<SensorSpec> parse_sensor_spec(std::string_view text, std::string& error) {
  text = trim(text);
  SensorSpec spec;
  const auto colon = text.find(':');
  spec.kind = std::string(trim(text.substr(0, colon)));
  const std::string_view rest = colon == std::string_view::npos ? "" : text.substr(colon + 1);

  bool known = spec.kind == "auto";
  for (const Kind& kind : kinds) known = known || kind.name == spec.kind;
  if (!known) {
    error = "unknown sensor \"" + spec.kind + "\" (expected auto, nvml, amdgpu, rapl, i915, xe, cpu or file:PATH)";
    return std::nullopt;
  }
  if (spec.kind == "file") {
    if (rest.empty()) {
      error = "the file sensor needs a path: file:PATH";
      return std::nullopt;
    }
    spec.path = std::string(rest);
    return spec;
  }
  std::string_view params = rest;
  while (!params.empty()) {
    const auto comma = params.find(',');
    const std::string_view item = trim(params.substr(0, comma));
    params = comma == std::string_view::npos ? "" : params.substr(comma + 1);
    const auto eq = item.find('=');
    if (eq == std::string_view::npos || trim(item.substr(0, eq)).empty()) {
      error = "sensor parameter \"" + std::string(item) + "\" is not key=value";
      return std::nullopt;
    }
    spec.params[std::string(trim(item.substr(0, eq)))] = std::string(trim(item.substr(eq + 1)));
  }
  return spec;
}

bool only_params(const SensorSpec& spec, std::initializer_list<std::string_view> allowed, std::string& error) {
  for (const auto& [key, value] : spec.params) {
    bool ok = false;
    for (auto a : allowed) ok = ok || a == key;
    if (!ok) {
      error = spec.kind + " sensor has no parameter \"" + key + "\"";
      return false;
    }
  }
  return true;
}

bool param_number(const SensorSpec& spec, const std::string& key, double& value, std::string& error) {
  const auto it = spec.params.find(key);
  if (it == spec.params.end()) return true;
  const std::string& text = it->second;
  double parsed = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  if (ec != std::errc() || ptr != text.data() + text.size() || !std::isfinite(parsed)) {
    error = spec.kind + " sensor: " + key + "=\"" + text + "\" is not a number";
    return false;
  }
  value = parsed;
  return true;
}

bool param_index(const SensorSpec& spec, const std::string& key, unsigned& value, std::string& error) {
  const auto it = spec.params.find(key);
  if (it == spec.params.end()) return true;
  const std::string& text = it->second;
  unsigned parsed = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), parsed);
  if (ec != std::errc() || ptr != text.data() + text.size()) {
    error = spec.kind + " sensor: " + key + "=\"" + text + "\" is not a non-negative integer";
    return false;
  }
  value = parsed;
  return true;
}

SourceEnvironment SourceEnvironment::from_process_environment() {
  SourceEnvironment env;
  if (const char* root = std::getenv("GLBUDGET_SYSFS_ROOT"); root && *root) env.sysfs_root = root;
  if (const char* lib = std::getenv("GLBUDGET_NVML_LIBRARY"); lib && *lib) env.nvml_library = lib;
  return env;
}

const std::vector<std::string>& auto_order() {
  static const std::vector<std::string> order = [] {
    std::vector<std::string> names;
    for (const Kind& kind : kinds)
      if (kind.name != "file") names.emplace_back(kind.name);
    return names;
  }();
  return order;
}

std::vector<ProbeResult> probe_all(const SourceEnvironment& env) {
  std::vector<ProbeResult> results;
  for (const auto& name : auto_order()) {
    SensorSpec spec;
    spec.kind = name;
    results.push_back(ProbeResult{name, open_source(spec, env)});
  }
  return results;
}

OpenResult open_source(const SensorSpec& spec, const SourceEnvironment& env) {
  if (spec.kind == "auto") {
    if (!spec.params.empty()) return unavailable("the auto sensor takes no parameters");
    std::string tried;
    for (const auto& name : auto_order()) {
      SensorSpec candidate;
      candidate.kind = name;
      OpenResult result = open_source(candidate, env);
      if (result.source) return result;
      tried += (tried.empty() ? "" : "; ") + name + ": " + result.why_not;
    }
    return unavailable("no sensor available (" + tried + ")");
  }
  for (const Kind& kind : kinds)
    if (kind.name == spec.kind) return kind.open(spec, env);
  return unavailable("unknown sensor \"" + spec.kind + "\"");
}

}  // namespace glbudget::sensors
