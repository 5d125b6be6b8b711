#include "fake_sysfs.hpp"

#include <cstdlib>
#include <fstream>
#include <stdexcept>

namespace glbudget::sensors::testing {

namespace fs = std::filesystem;

FakeSysfs::FakeSysfs() {
  std::string pattern = (fs::temp_directory_path() / "glbudget-sysfs-XXXXXX").string();
  if (!mkdtemp(pattern.data())) throw std::runtime_error("mkdtemp failed");
  root_ = pattern;
}

FakeSysfs::~FakeSysfs() {
  std::error_code ec;
  fs::remove_all(root_, ec);
}

void FakeSysfs::write(const std::string& relative, const std::string& text) const {
  const fs::path path = root_ / relative;
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::trunc) << text << '\n';
}

void FakeSysfs::remove(const std::string& relative) const { fs::remove(root_ / relative); }

void FakeSysfs::add_hwmon(int number, const std::string& name) const {
  write("class/hwmon/hwmon" + std::to_string(number) + "/name", name);
}

void FakeSysfs::add_rapl_zone(const std::string& zone, const std::string& name, std::uint64_t energy_uj,
                              std::uint64_t max_range_uj) const {
  write("class/powercap/" + zone + "/name", name);
  write("class/powercap/" + zone + "/energy_uj", std::to_string(energy_uj));
  write("class/powercap/" + zone + "/max_energy_range_uj", std::to_string(max_range_uj));
}

}  // namespace glbudget::sensors::testing
