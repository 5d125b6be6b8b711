// GLBUDGET_SENSOR handling: good values are honoured, bad ones fall back to auto.
#include <catch2/catch.hpp>
#include <cstdlib>

#include "fake_sysfs.hpp"
#include "glbudget/sensors/sensor.hpp"

using namespace glbudget::sensors;
using glbudget::sensors::testing::FakeSysfs;

namespace {

// Runs with an empty fake machine (no GPU, no RAPL), so auto ends at the cpu estimate.
std::unique_ptr<PowerSensor> open_with(const FakeSysfs& sysfs, const char* value) {
  setenv("GLBUDGET_SYSFS_ROOT", sysfs.root().c_str(), 1);
  setenv("GLBUDGET_NVML_LIBRARY", "/nonexistent/libnvidia-ml.so.1", 1);
  if (value)
    setenv("GLBUDGET_SENSOR", value, 1);
  else
    unsetenv("GLBUDGET_SENSOR");
  auto sensor = open_sensor_from_environment();
  unsetenv("GLBUDGET_SYSFS_ROOT");
  unsetenv("GLBUDGET_NVML_LIBRARY");
  unsetenv("GLBUDGET_SENSOR");
  return sensor;
}

}  // namespace

TEST_CASE("GLBUDGET_SENSOR selects and parameterises the sensor", "[environment]") {
  FakeSysfs sysfs;
  sysfs.add_hwmon(0, "i915");
  sysfs.write("class/hwmon/hwmon0/energy1_input", "5");
  auto sensor = open_with(sysfs, "cpu:idle=5,max=20");
  REQUIRE(sensor);
  CHECK(sensor->name() == "cpu");
  CHECK(sensor->description().find("5 W + (20 W - 5 W)") != std::string::npos);

  sensor = open_with(sysfs, nullptr);  // unset means auto: the i915 counter wins over cpu
  REQUIRE(sensor);
  CHECK(sensor->name() == "i915");
}

TEST_CASE("bad or unavailable GLBUDGET_SENSOR values fall back to auto", "[environment]") {
  FakeSysfs sysfs;
  for (const char* value : {"bogus", "rapl", "cpu:idle=x", "file:/nonexistent/meter", ""}) {
    INFO(value);
    auto sensor = open_with(sysfs, value);
    REQUIRE(sensor);
    CHECK(sensor->name() == "cpu");
    CHECK(sensor->is_estimate());
  }
}

TEST_CASE("sampling periods parse as whole milliseconds in 1..1000", "[environment]") {
  using std::chrono::milliseconds;
  CHECK(parse_sampling_period_ms("1") == milliseconds(1));
  CHECK(parse_sampling_period_ms("1000") == milliseconds(1000));
  for (const char* bad : {"", "0", "1001", "-5", "5ms", " 5", "2.5", "99999999999999999999"}) {
    CAPTURE(bad);
    CHECK(!parse_sampling_period_ms(bad));
  }
}

TEST_CASE("GLBUDGET_SENSOR_PERIOD_MS sets the sampling period; bad values keep the default", "[environment]") {
  FakeSysfs sysfs;
  using std::chrono::milliseconds;
  const std::pair<const char*, milliseconds> cases[] = {{"0", milliseconds(5)},
                                                        {"abc", milliseconds(5)},
                                                        {"5000", milliseconds(5)},
                                                        {"2", milliseconds(2)},
                                                        {"1000", milliseconds(1000)}};
  for (const auto& [period, expected] : cases) {
    INFO(period);
    setenv("GLBUDGET_SENSOR_PERIOD_MS", period, 1);
    auto sensor = open_with(sysfs, "cpu");
    unsetenv("GLBUDGET_SENSOR_PERIOD_MS");
    REQUIRE(sensor);
    CHECK(sensor->period() == expected);
  }
}
