#include "shim_path.hpp"

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "glbudget/sensors/profile_path.hpp"

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

}  // namespace

std::string preload_with_shim(const std::string& shim, const char* inherited) {
  std::string preload = shim;
#ifdef GLBUDGET_SANITIZER_PRELOAD
  preload = std::string(GLBUDGET_SANITIZER_PRELOAD) + ":" + preload;
#endif
  if (inherited && *inherited) preload += std::string(":") + inherited;
  return preload;
}

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
  std::vector<fs::path> candidates = {dir / ".." / build_dir / name, dir / "../lib/glbudget" / name};
#ifdef GLBUDGET_MULTIARCH
  candidates.insert(candidates.begin() + 1, dir / "../lib" / GLBUDGET_MULTIARCH / "glbudget" / name);
#endif
  return first_file(candidates);
}

std::string default_profile(const std::string& sensor) { return sensors::default_profile_path(sensor); }

}  // namespace glbudget::cli
