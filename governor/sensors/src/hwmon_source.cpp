// Sources reading one attribute of a hwmon device (amdgpu, i915, xe).
#include "hwmon_source.hpp"

#include "sysfs.hpp"

namespace glbudget::sensors {

namespace {

class HwmonAttributeSource final : public Source {
 public:
  HwmonAttributeSource(std::string_view name, std::filesystem::path attribute, ReadingKind kind)
      : name_(name), attribute_(std::move(attribute)), kind_(kind) {}

  std::string_view name() const override { return name_; }
  std::string description() const override {
    return (kind_ == ReadingKind::energy_j ? "energy counter " : "power ") + attribute_.string();
  }
  Reading read(std::int64_t) override {
    return sysfs::read_scaled(attribute_, 1e-6, kind_);  // hwmon units: µJ and µW
  }

 private:
  std::string_view name_;  // a literal: see Source::name()
  std::filesystem::path attribute_;
  ReadingKind kind_;
};

}  // namespace

OpenResult open_hwmon(const SensorSpec& spec, const SourceEnvironment& env, std::string_view hwmon_name,
                      std::initializer_list<HwmonAttribute> preference) {
  std::string error;
  unsigned index = 0;
  if (!only_params(spec, {"index"}, error) || !param_index(spec, "index", index, error)) return unavailable(error);
  const auto dirs = sysfs::hwmon_named(env.sysfs_root, std::string(hwmon_name));
  if (dirs.empty())
    return unavailable("no hwmon named " + std::string(hwmon_name) + " under " +
                       (env.sysfs_root / "class" / "hwmon").string());
  if (index >= dirs.size())
    return unavailable("index=" + std::to_string(index) + " but only " + std::to_string(dirs.size()) + " " +
                       std::string(hwmon_name) + " hwmon found");
  std::string tried;
  for (const HwmonAttribute& attribute : preference) {
    const auto path = dirs[index] / attribute.file;
    const Reading probe = sysfs::read_scaled(path, 1e-6, attribute.kind);
    if (probe.status == ReadStatus::ok)
      return OpenResult{std::make_unique<HwmonAttributeSource>(hwmon_name, path, attribute.kind), {}};
    tried += (tried.empty() ? "" : "; ") + probe.detail;
  }
  return unavailable(tried);
}

}  // namespace glbudget::sensors
