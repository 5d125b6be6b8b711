#include <catch2/catch.hpp>
#include <limits>

#include "glbudget/sensors/power_log.hpp"

using namespace glbudget::sensors;

TEST_CASE("power log fields: measured, estimated, and missing", "[log]") {
  std::string row = "7,";
  append_power_fields(row, FrameEnergy{true, 0.5, 30.0, "rapl", false, 0});
  CHECK(row == "7,30,0.5,rapl");

  row.clear();
  append_power_fields(row, FrameEnergy{true, 1.23456789e-3, 12.3456789, "cpu", true, 0});
  CHECK(row == "12.3457,0.00123456789,cpu~estimate");

  const double nan = std::numeric_limits<double>::quiet_NaN();
  row.clear();
  append_power_fields(row, FrameEnergy{false, nan, nan, "nvml", false, 4});
  CHECK(row == ",,nvml");
  CHECK(power_log_columns == "power_w,energy_j,sensor");
}
