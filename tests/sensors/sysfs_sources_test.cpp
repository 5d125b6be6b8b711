// amdgpu, rapl, i915 and xe against fake sysfs trees.
#include <catch2/catch.hpp>
#include <cmath>

#include "fake_sysfs.hpp"
#include "glbudget/sensors/energy_integrator.hpp"
#include "glbudget/sensors/registry.hpp"

#include "nanoseconds.hpp"

using namespace glbudget::sensors;
using glbudget::sensors::testing::FakeSysfs;

namespace {

OpenResult open(const FakeSysfs& sysfs, const std::string& text) {
  std::string error;
  const auto spec = parse_sensor_spec(text, error);
  REQUIRE(spec);
  SourceEnvironment env;
  env.sysfs_root = sysfs.root();
  return open_source(*spec, env);
}

}  // namespace

TEST_CASE("amdgpu prefers energy, then power1_average, then power1_input", "[amdgpu]") {
  FakeSysfs sysfs;
  sysfs.add_hwmon(0, "k10temp");
  sysfs.add_hwmon(3, "amdgpu");
  sysfs.write("class/hwmon/hwmon3/power1_input", "55000000");

  auto opened = open(sysfs, "amdgpu");
  REQUIRE(opened.source);
  CHECK(opened.source->name() == "amdgpu");
  CHECK(opened.source->description().find("power1_input") != std::string::npos);
  Reading r = opened.source->read(0);
  CHECK(r.status == ReadStatus::ok);
  CHECK(r.kind == ReadingKind::power_w);
  CHECK(r.value == Approx(55.0));

  sysfs.write("class/hwmon/hwmon3/power1_average", "41500000");
  opened = open(sysfs, "amdgpu");
  REQUIRE(opened.source);
  r = opened.source->read(0);
  CHECK(r.kind == ReadingKind::power_w);
  CHECK(r.value == Approx(41.5));

  sysfs.write("class/hwmon/hwmon3/energy1_input", "123456789");
  opened = open(sysfs, "amdgpu");
  REQUIRE(opened.source);
  r = opened.source->read(0);
  CHECK(r.kind == ReadingKind::energy_j);
  CHECK(r.value == Approx(123.456789));
}

TEST_CASE("amdgpu is unavailable without its hwmon, and says why", "[amdgpu]") {
  FakeSysfs sysfs;
  sysfs.add_hwmon(0, "amdgpu");  // present, but with nothing to read
  auto opened = open(sysfs, "amdgpu");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("power1_input") != std::string::npos);
  opened = open(sysfs, "amdgpu:index=1");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("only 1") != std::string::npos);
  FakeSysfs empty;
  opened = open(empty, "amdgpu");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("no hwmon named amdgpu") != std::string::npos);
}

TEST_CASE("i915 and xe read energy1_input", "[intel]") {
  for (const std::string kind : {"i915", "xe"}) {
    FakeSysfs sysfs;
    sysfs.add_hwmon(1, kind);
    sysfs.write("class/hwmon/hwmon1/energy1_input", "2000000");
    auto opened = open(sysfs, kind);
    REQUIRE(opened.source);
    CHECK(opened.source->name() == kind);
    Reading r = opened.source->read(0);
    CHECK(r.kind == ReadingKind::energy_j);
    CHECK(r.value == Approx(2.0));
  }
}

TEST_CASE("a hwmon attribute that vanishes or returns garbage is reported, not thrown", "[intel][faults]") {
  FakeSysfs sysfs;
  sysfs.add_hwmon(0, "xe");
  sysfs.write("class/hwmon/hwmon0/energy1_input", "1000000");
  auto opened = open(sysfs, "xe");
  REQUIRE(opened.source);
  Source& source = *opened.source;

  sysfs.write("class/hwmon/hwmon0/energy1_input", "nan");
  Reading r = source.read(0);
  // "nan" parses as a number: the integrator is the one that rejects it.
  EnergyIntegrator integrator;
  CHECK(integrator.accept(1, r).fault == Fault::garbage);

  sysfs.write("class/hwmon/hwmon0/energy1_input", "12ab");
  CHECK(source.read(0).status == ReadStatus::garbage);
  sysfs.write("class/hwmon/hwmon0/energy1_input", "");
  CHECK(source.read(0).status == ReadStatus::garbage);

  sysfs.remove("class/hwmon/hwmon0/energy1_input");
  r = source.read(0);
  CHECK(r.status == ReadStatus::read_error);
  CHECK(r.detail.find("energy1_input") != std::string::npos);
}

TEST_CASE("rapl sums the packages and unwraps each counter at max_energy_range_uj", "[rapl]") {
  FakeSysfs sysfs;
  const std::uint64_t range = 262143328850;  // a typical max_energy_range_uj
  sysfs.add_rapl_zone("intel-rapl:0", "package-0", range - 1'000'000, range);
  sysfs.add_rapl_zone("intel-rapl:1", "package-1", 5'000'000, range);
  sysfs.add_rapl_zone("intel-rapl:0:0", "core", 7, range);
  sysfs.add_rapl_zone("intel-rapl:2", "psys", 9, range);

  auto opened = open(sysfs, "rapl");
  REQUIRE(opened.source);
  CHECK(opened.source->description().find("intel-rapl:1") != std::string::npos);
  CHECK(opened.source->description().find("intel-rapl:0:0") == std::string::npos);
  Source& source = *opened.source;
  CHECK(source.read(0).value == 0.0);

  // package-0 wraps: 1 J before the top, 2 J after zero = 3 J; package-1 adds 0.5 J.
  sysfs.write("class/powercap/intel-rapl:0/energy_uj", "2000000");
  sysfs.write("class/powercap/intel-rapl:1/energy_uj", "5500000");
  Reading r = source.read(0);
  CHECK(r.status == ReadStatus::ok);
  CHECK(r.kind == ReadingKind::energy_j);
  CHECK(r.value == Approx(3.5));

  sysfs.write("class/powercap/intel-rapl:0/energy_uj", "2100000");
  CHECK(source.read(0).value == Approx(3.6));
}

TEST_CASE("rapl reads a named domain, such as the integrated GPU's uncore", "[rapl]") {
  FakeSysfs sysfs;
  sysfs.add_rapl_zone("intel-rapl:0", "package-0", 100, 1000000);
  sysfs.add_rapl_zone("intel-rapl:0:1", "uncore", 1000, 1000000);
  auto opened = open(sysfs, "rapl:domain=uncore");
  REQUIRE(opened.source);
  opened.source->read(0);
  sysfs.write("class/powercap/intel-rapl:0:1/energy_uj", "251000");
  CHECK(opened.source->read(0).value == Approx(0.25));

  CHECK_FALSE(open(sysfs, "rapl:domain=dram").source);
  const auto bad = open(sysfs, "rapl:domain=gpu");
  CHECK_FALSE(bad.source);
  CHECK(bad.why_not.find("not package") != std::string::npos);
}

TEST_CASE("a rapl counter that really goes backwards is rejected downstream", "[rapl][faults]") {
  FakeSysfs sysfs;
  const std::uint64_t range = 262143328850;
  sysfs.add_rapl_zone("intel-rapl:0", "package-0", 50'000'000, range);
  auto opened = open(sysfs, "rapl");
  REQUIRE(opened.source);
  EnergyIntegrator integrator;
  integrator.accept(0, opened.source->read(0));
  sysfs.write("class/powercap/intel-rapl:0/energy_uj", "49000000");  // 1 J backwards
  // Read as a wrap it would be 262 kJ in 10 ms: implausible, so dropped.
  const auto outcome = integrator.accept(10 * ms, opened.source->read(10 * ms));
  CHECK(outcome.fault == Fault::garbage);
  sysfs.write("class/powercap/intel-rapl:0/energy_uj", "49100000");
  const auto next = integrator.accept(20 * ms, opened.source->read(20 * ms));
  REQUIRE(next.point);
  CHECK(next.point->energy_j == Approx(0.1));
}

TEST_CASE("rapl without powercap says where it looked", "[rapl]") {
  FakeSysfs sysfs;
  const auto opened = open(sysfs, "rapl");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("powercap") != std::string::npos);
}
