// Integration (issue 4): the demo renderer under the shim with the cpu sensor logs power per
// frame, and it rises with the configuration's cost and falls with GLBUDGET_FPS pacing.
// The cpu sensor's defaults: idle 10 W, max 45 W, so its range is 35 W.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <map>

#include "probe_expectations.hpp"

namespace {
constexpr double kRangeW = 45.0 - 10.0;

struct PowerRun {
  double mean_power_w = NAN;
  size_t frames_with_power = 0;
  std::string sensor;
};

// Hall at a small detail and size, 10 frames; mean power over the frames after the first two
// (the sensor needs two swaps before its first valid frame; the first frames compile shaders).
PowerRun run_demo(const std::string& config, const std::string& fps) {
  std::string log = temp_path("power_" + config + "_" + fps + ".csv");
  unlink(log.c_str());
  auto r = run_process(
      {DEMO_PATH, "--scene", "hall", "--detail", "0.05", "--width", "256", "--height", "144", "--frames", "10",
       "--config", config},
      {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}, {"GLBUDGET_SENSOR", "cpu"}, {"GLBUDGET_FPS", fps}});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  auto rows = read_csv_rows_by_name(log);
  REQUIRE(rows.size() > 0);
  std::map<long, double> power_by_frame;
  PowerRun run;
  for (const auto& row : rows) {
    REQUIRE(row.count("power_w"));
    REQUIRE(row.count("energy_j"));
    REQUIRE(row.count("sensor"));
    run.sensor = row.at("sensor");
    if (row.at("power_w").empty()) continue;
    long frame = std::stol(row.at("frame"));
    double p = std::stod(row.at("power_w"));
    CHECK(std::stod(row.at("energy_j")) > 0);
    if (power_by_frame.count(frame)) CHECK(power_by_frame[frame] == p);  // one value per frame, on every pass row
    power_by_frame[frame] = p;
  }
  run.frames_with_power = power_by_frame.size();
  double sum = 0;
  size_t n = 0;
  for (auto& [frame, p] : power_by_frame) {
    CHECK(p >= 10.0 - 1e-9);
    CHECK(p <= 45.0 + 1e-9);
    if (frame > 2) sum += p, ++n;
  }
  run.mean_power_w = n ? sum / n : NAN;
  unlink(log.c_str());
  return run;
}
}  // namespace

TEST_CASE("cpu-sensor power in the log rises with the configuration's cost and falls with pacing", "[integration]") {
  // Paced at 3 fps, a frame of either configuration fits the period, so the difference in
  // CPU time per frame shows as a difference in utilisation and so in estimated power.
  // At 256x144 the gap is about 5 W idle (16.6 vs 11.3 W); at 128x72 it was 2.2 W, and under
  // ctest -j2 on CI it once fell to 1.66 W, under the 1.75 W asked for.
  PowerRun best = run_demo("0,0,0,0,0,0", "3");
  PowerRun cheapest = run_demo("2,2,2,2,2,2", "3");
  PowerRun cheapest_unpaced = run_demo("2,2,2,2,2,2", "off");
  for (const PowerRun* r : {&best, &cheapest, &cheapest_unpaced}) {
    CHECK(r->sensor == "cpu~estimate");  // always labelled an estimate
    CHECK(r->frames_with_power >= 8);
  }
  INFO("best " << best.mean_power_w << " W, cheapest " << cheapest.mean_power_w << " W, cheapest unpaced "
               << cheapest_unpaced.mean_power_w << " W");
  CHECK(best.mean_power_w > cheapest.mean_power_w + 0.05 * kRangeW);
  // Unpaced, the renderer is CPU-bound: how much of the 2 cores it gets depends on what else
  // runs (ctest -j2 runs another test beside it), so the margin asked for is a modest one.
  CHECK(cheapest_unpaced.mean_power_w > cheapest.mean_power_w + 0.10 * kRangeW);
}
