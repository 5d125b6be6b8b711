#pragma once
// A throw-away directory tree standing in for /sys in tests (SourceEnvironment::sysfs_root).
#include <filesystem>
#include <string>

namespace glbudget::sensors::testing {

class FakeSysfs {
 public:
  FakeSysfs();
  ~FakeSysfs();
  FakeSysfs(const FakeSysfs&) = delete;
  FakeSysfs& operator=(const FakeSysfs&) = delete;

  const std::filesystem::path& root() const { return root_; }
  // Writes `text` (plus a newline, as sysfs does) to root/relative, creating directories.
  void write(const std::string& relative, const std::string& text) const;
  void remove(const std::string& relative) const;

  // Builders for the layouts the sources look for.
  void add_hwmon(int number, const std::string& name) const;  // class/hwmon/hwmonN/name
  void add_rapl_zone(const std::string& zone, const std::string& name, std::uint64_t energy_uj,
                     std::uint64_t max_range_uj) const;  // class/powercap/<zone>/...

 private:
  std::filesystem::path root_;
};

}  // namespace glbudget::sensors::testing
