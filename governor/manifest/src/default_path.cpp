#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "glbudget/manifest/manifest.hpp"

namespace glbudget::manifest {

std::string default_manifest_path(const std::string& executable) {
  std::string base;
  if (const char* xdg = std::getenv("XDG_CONFIG_HOME"); xdg && *xdg)
    base = xdg;
  else if (const char* home = std::getenv("HOME"); home && *home)
    base = std::string(home) + "/.config";
  if (base.empty() || executable.empty()) return {};
  const std::string path = base + "/glbudget/" + executable + ".toml";
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec) ? path : std::string();
}

}  // namespace glbudget::manifest
