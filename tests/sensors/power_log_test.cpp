#include <catch2/catch.hpp>
#include <limits>
#include <string>

#include "glbudget/sensors/power_log.hpp"

using namespace glbudget::sensors;

namespace {
std::string format(const FrameEnergy& frame) {
  char out[128];
  const int n = format_power_fields(frame, out, sizeof out);
  REQUIRE(n >= 0);
  REQUIRE(n < static_cast<int>(sizeof out));
  return std::string(out, static_cast<std::size_t>(n));
}
}  // namespace

TEST_CASE("power log fields: measured, estimated, and missing", "[log]") {
  CHECK(format(FrameEnergy{true, 0.5, 30.0, "rapl", false, 0}) == "30,0.5,rapl");
  CHECK(format(FrameEnergy{true, 1.23456789e-3, 12.3456789, "cpu", true, 0}) == "12.3457,0.00123456789,cpu~estimate");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  CHECK(format(FrameEnergy{false, nan, nan, "nvml", false, 4}) == ",,nvml");
  CHECK(power_log_columns == "power_w,energy_j,sensor");
}

TEST_CASE("power log fields report their length when the buffer is too small", "[log]") {
  char tiny[4];
  const int n = format_power_fields(FrameEnergy{true, 0.5, 30.0, "rapl", false, 0}, tiny, sizeof tiny);
  CHECK(n == 11);
  CHECK(std::string(tiny) == "30,");
}
