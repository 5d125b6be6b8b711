// The nvml sensor against a fake libnvidia-ml built with the tests (fake_nvml.c).
#include <catch2/catch.hpp>
#include <cstdlib>

#include "glbudget/sensors/registry.hpp"

using namespace glbudget::sensors;

namespace {

OpenResult open_nvml(const char* mode, const std::string& spec_text = "nvml",
                     const std::string& library = FAKE_NVML_LIBRARY) {
  setenv("FAKE_NVML_MODE", mode, 1);
  std::string error;
  const auto spec = parse_sensor_spec(spec_text, error);
  REQUIRE(spec);
  SourceEnvironment env;
  env.nvml_library = library;
  return open_source(*spec, env);
}

}  // namespace

TEST_CASE("nvml reads the total energy counter where the GPU has one", "[nvml]") {
  auto opened = open_nvml("energy");
  REQUIRE(opened.source);
  CHECK(opened.source->name() == "nvml");
  CHECK(opened.source->description().find("energy") != std::string::npos);
  const Reading a = opened.source->read(0);
  const Reading b = opened.source->read(0);
  CHECK(a.status == ReadStatus::ok);
  CHECK(a.kind == ReadingKind::energy_j);
  CHECK(b.value - a.value == Approx(0.025));  // 25 mJ per read, in joules
}

TEST_CASE("nvml falls back to power usage and says it is a 1-second average", "[nvml]") {
  auto opened = open_nvml("power");
  REQUIRE(opened.source);
  CHECK(opened.source->description().find("1 s") != std::string::npos);
  const Reading r = opened.source->read(0);
  CHECK(r.kind == ReadingKind::power_w);
  CHECK(r.value == Approx(42.5));
}

TEST_CASE("nvml without a driver or library is unavailable, with the reason", "[nvml]") {
  auto opened = open_nvml("no_driver");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("Driver Not Loaded") != std::string::npos);

  opened = open_nvml("energy", "nvml", "/nonexistent/libnvidia-ml.so.1");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("cannot load") != std::string::npos);

  opened = open_nvml("energy", "nvml:device=1");
  CHECK_FALSE(opened.source);
  CHECK(opened.why_not.find("GPU 1") != std::string::npos);
}

TEST_CASE("a GPU that falls off the bus gives read errors, not a crash", "[nvml][faults]") {
  auto opened = open_nvml("lost");
  REQUIRE(opened.source);  // the probe at open used one read
  CHECK(opened.source->read(0).status == ReadStatus::ok);
  CHECK(opened.source->read(0).status == ReadStatus::ok);
  const Reading lost = opened.source->read(0);
  CHECK(lost.status == ReadStatus::read_error);
  CHECK(lost.detail == "GPU is lost");
}
