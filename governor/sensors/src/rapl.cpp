// rapl: the powercap interface of Intel (and AMD Zen) CPUs. Each zone has a cumulative
// energy_uj counter that wraps at max_energy_range_uj.
#include <cerrno>
#include <cstdint>
#include <vector>

#include "sources.hpp"
#include "sysfs.hpp"

namespace glbudget::sensors {

namespace {

namespace fs = std::filesystem;

struct Zone {
  fs::path dir;
  double range_j = 0.0;  // the counter wraps to zero after this
  double last_raw_j = 0.0;
  bool have_last = false;
};

class RaplSource final : public Source {
 public:
  RaplSource(std::vector<Zone> zones, std::string domain) : zones_(std::move(zones)), domain_(std::move(domain)) {}

  std::string_view name() const override { return "rapl"; }
  std::string description() const override {
    std::string text = domain_ + " energy_uj of";
    for (const Zone& zone : zones_) text += " " + zone.dir.string();
    return text;
  }

  Reading read(std::int64_t) override {
    // Read every zone first so that a failure leaves all of them at their last good value.
    std::vector<double> raw(zones_.size());
    for (std::size_t i = 0; i < zones_.size(); ++i) {
      Reading r = sysfs::read_scaled(zones_[i].dir / "energy_uj", 1e-6, ReadingKind::energy_j);
      if (r.status != ReadStatus::ok) return r;
      raw[i] = r.value;
    }
    for (std::size_t i = 0; i < zones_.size(); ++i) {
      Zone& zone = zones_[i];
      if (zone.have_last) {
        double delta = raw[i] - zone.last_raw_j;
        // A smaller value is a wrap-around. A counter that really went backwards shows up as
        // a jump of nearly the whole range, which the Sampler rejects as implausible.
        if (delta < 0.0 && zone.range_j > 0.0) delta += zone.range_j;
        total_j_ += delta;
      }
      zone.last_raw_j = raw[i];
      zone.have_last = true;
    }
    return Reading{ReadStatus::ok, ReadingKind::energy_j, total_j_, {}};
  }

 private:
  std::vector<Zone> zones_;
  std::string domain_;
  double total_j_ = 0.0;
};

bool zone_matches(const std::string& zone_name, const std::string& domain) {
  if (domain == "package") return zone_name.starts_with("package-");
  return zone_name == domain;
}

}  // namespace

OpenResult open_rapl(const SensorSpec& spec, const SourceEnvironment& env) {
  std::string error;
  if (!only_params(spec, {"domain"}, error)) return unavailable(error);
  const auto domain_it = spec.params.find("domain");
  const std::string domain = domain_it == spec.params.end() ? "package" : domain_it->second;
  if (domain != "package" && domain != "uncore" && domain != "core" && domain != "dram" && domain != "psys")
    return unavailable("rapl domain \"" + domain + "\" is not package, uncore, core, dram or psys");

  const fs::path powercap = env.sysfs_root / "class" / "powercap";
  // Top-level zones are intel-rapl:N, their subzones intel-rapl:N:M.
  std::vector<Zone> zones;
  for (const auto& dir : sysfs::entries_with_prefix(powercap, "intel-rapl:")) {
    if (zone_matches(sysfs::read_text(dir / "name").value_or(""), domain)) zones.push_back({dir});
  }
  if (zones.empty()) return unavailable("no powercap zone named " + domain + " under " + powercap.string());

  for (Zone& zone : zones) {
    const Reading range = sysfs::read_scaled(zone.dir / "max_energy_range_uj", 1e-6, ReadingKind::energy_j);
    if (range.status == ReadStatus::ok) zone.range_j = range.value;
    std::string read_error;
    int read_errno = 0;
    if (!sysfs::read_text(zone.dir / "energy_uj", &read_error, &read_errno)) {
      if (read_errno == EACCES)
        return unavailable((zone.dir / "energy_uj").string() +
                           " is readable by root only (Linux 5.10+, CVE-2020-8694); allow it "
                           "with: sudo chmod a+r " +
                           (powercap / "intel-rapl:*" / "energy_uj").string() + " (or a udev rule)");
      return unavailable(read_error);
    }
  }
  return OpenResult{std::make_unique<RaplSource>(std::move(zones), domain), {}};
}

}  // namespace glbudget::sensors
