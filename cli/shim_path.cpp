#include "shim_path.hpp"

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "glbudget/sensors/registry.hpp"

namespace glbudget::cli {

namespace {

namespace fs = std::filesystem;

fs::path own_directory() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path() : self.parent_path();
}

std::string first_file(const std::vector<fs::path>& candidates) {
  std::error_code ec;
  for (const fs::path& p : candidates)
    if (fs::is_regular_file(p, ec)) return fs::weakly_canonical(p, ec).string();
  return {};
}

// The kind a sensor spec names; "auto" resolved as the shim resolves it.
std::string sensor_kind(const std::string& sensor) {
  const std::string kind = sensor.empty() ? "auto" : sensor.substr(0, sensor.find(':'));
  if (kind != "auto") return kind;
  std::string error;
  const auto spec = sensors::parse_sensor_spec("auto", error);
  if (!spec) return kind;
  const sensors::OpenResult opened = sensors::open_source(*spec, sensors::SourceEnvironment::from_process_environment());
  return opened.source ? std::string(opened.source->name()) : kind;
}

}  // namespace

std::string find_shim() {
  if (const char* env = std::getenv("GLBUDGET_SHIM"); env && *env) return env;
  const fs::path dir = own_directory();
  if (dir.empty()) return {};
  std::vector<fs::path> candidates = {dir / "../interpose/libglbudget.so", dir / "../lib/glbudget/libglbudget.so"};
#ifdef GLBUDGET_MULTIARCH
  candidates.insert(candidates.begin() + 1, dir / "../lib" / GLBUDGET_MULTIARCH / "glbudget/libglbudget.so");
#endif
  return first_file(candidates);
}

std::string find_helper(const char* name, const char* build_dir, const char* env_variable) {
  if (const char* env = std::getenv(env_variable); env && *env) return env;
  const fs::path dir = own_directory();
  if (dir.empty()) return {};
  return first_file({dir / ".." / build_dir / name, dir / "../lib/glbudget" / name});
}

std::string default_profile(const std::string& sensor) {
  std::string base;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) base = xdg;
  else if (const char* home = std::getenv("HOME"); home && *home) base = std::string(home) + "/.cache";
  if (base.empty()) return {};
  return base + "/glbudget/" + sensor_kind(sensor) + ".json";
}

}  // namespace glbudget::cli
