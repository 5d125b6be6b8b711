#include <catch2/catch.hpp>

#include "fake_sysfs.hpp"
#include "glbudget/sensors/registry.hpp"

using namespace glbudget::sensors;
using glbudget::sensors::testing::FakeSysfs;

TEST_CASE("sensor specs parse kind, parameters and file paths", "[registry]") {
  std::string error;
  auto spec = parse_sensor_spec(" cpu:idle=8, max=40.5 ,cores=2 ", error);
  REQUIRE(spec);
  CHECK(spec->kind == "cpu");
  CHECK(spec->params.at("idle") == "8");
  CHECK(spec->params.at("max") == "40.5");
  CHECK(spec->params.at("cores") == "2");

  spec = parse_sensor_spec("file:/tmp/a:b,c=d", error);  // the path is taken verbatim
  REQUIRE(spec);
  CHECK(spec->kind == "file");
  CHECK(spec->path == "/tmp/a:b,c=d");
  CHECK(spec->params.empty());

  spec = parse_sensor_spec("rapl", error);
  REQUIRE(spec);
  CHECK(spec->params.empty());
}

TEST_CASE("bad sensor specs are refused with a message", "[registry]") {
  std::string error;
  CHECK_FALSE(parse_sensor_spec("nvidia", error));
  CHECK(error.find("unknown sensor \"nvidia\"") != std::string::npos);
  CHECK_FALSE(parse_sensor_spec("", error));
  CHECK_FALSE(parse_sensor_spec("file:", error));
  CHECK(error.find("needs a path") != std::string::npos);
  CHECK_FALSE(parse_sensor_spec("cpu:idle", error));
  CHECK(error.find("key=value") != std::string::npos);
  CHECK_FALSE(parse_sensor_spec("cpu:=3", error));
}

TEST_CASE("bad parameters make a sensor unavailable, with the reason", "[registry]") {
  std::string error;
  const SourceEnvironment env;
  auto open = [&](const std::string& text) {
    auto spec = parse_sensor_spec(text, error);
    REQUIRE(spec);
    return open_source(*spec, env);
  };
  CHECK(open("cpu:idle=abc").why_not.find("not a number") != std::string::npos);
  CHECK(open("cpu:idle=50,max=10").why_not.find("idle <= max") != std::string::npos);
  CHECK(open("cpu:idle=-1").why_not.find("idle <= max") != std::string::npos);
  CHECK(open("cpu:idle=inf").why_not.find("not a number") != std::string::npos);
  CHECK(open("cpu:cores=0").why_not.find("cores >= 1") != std::string::npos);
  CHECK(open("cpu:cores=-2").why_not.find("non-negative integer") != std::string::npos);
  CHECK(open("cpu:watts=3").why_not.find("no parameter \"watts\"") != std::string::npos);
  CHECK(open("auto:x=1").why_not.find("no parameters") != std::string::npos);
  // Extremes that are still valid: a zero-power machine, and idle == max.
  CHECK(open("cpu:idle=0,max=0").source);
  CHECK(open("cpu:idle=30,max=30").source);
}

TEST_CASE("auto picks the best sensor present", "[registry]") {
  FakeSysfs sysfs;
  SourceEnvironment env;
  env.sysfs_root = sysfs.root();
  env.nvml_library = "/nonexistent/libnvidia-ml.so.1";
  const SensorSpec automatic{"auto", {}, {}};

  auto opened = open_source(automatic, env);
  REQUIRE(opened.source);
  CHECK(opened.source->name() == "cpu");  // nothing else on this machine
  CHECK(opened.source->is_estimate());

  sysfs.add_rapl_zone("intel-rapl:0", "package-0", 1, 1000000);
  opened = open_source(automatic, env);
  REQUIRE(opened.source);
  CHECK(opened.source->name() == "rapl");

  sysfs.add_hwmon(0, "amdgpu");
  sysfs.write("class/hwmon/hwmon0/power1_input", "1000000");
  opened = open_source(automatic, env);
  REQUIRE(opened.source);
  CHECK(opened.source->name() == "amdgpu");
}

TEST_CASE("probing lists every sensor kind, available or why not", "[registry]") {
  FakeSysfs sysfs;
  sysfs.add_rapl_zone("intel-rapl:0", "package-0", 1, 1000000);
  SourceEnvironment env;
  env.sysfs_root = sysfs.root();
  env.nvml_library = "/nonexistent/libnvidia-ml.so.1";
  const auto probes = probe_all(env);
  REQUIRE(probes.size() == auto_order().size());
  for (const auto& probe : probes) {
    INFO(probe.kind);
    const bool expected = probe.kind == "rapl" || probe.kind == "cpu";
    CHECK(static_cast<bool>(probe.opened.source) == expected);
    CHECK(expected == probe.opened.why_not.empty());
  }
}
