// Unit: the GLBUDGET_* parser and the frame-log row format (no GL involved).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <fstream>
#include <regex>
#include <string>
#include <vector>

#include "frame_log.hpp"
#include "options.hpp"
#include "parse_env.hpp"

using namespace glbudget;

TEST_CASE("GLBUDGET_FPS accepts positive rates and says why it refuses the rest", "[unit]") {
  std::string w;
  CHECK(parse_env({"GLBUDGET_FPS=30"}, &w).fps == 30);
  CHECK(parse_env({"GLBUDGET_FPS=59.94"}, &w).fps == Approx(59.94));
  CHECK(parse_env({"GLBUDGET_FPS=10000"}, &w).fps == 10000);
  CHECK(w.empty());
  for (const char* off : {"GLBUDGET_FPS=", "GLBUDGET_FPS=off", "GLBUDGET_FPS=0"}) {
    CHECK(parse_env({off}, &w).fps == 0);
    CHECK(w.empty());
  }
  for (const char* bad : {"GLBUDGET_FPS=fast", "GLBUDGET_FPS=-5", "GLBUDGET_FPS=30fps", "GLBUDGET_FPS=nan",
                          "GLBUDGET_FPS=inf", "GLBUDGET_FPS=1e9", "GLBUDGET_FPS=1e-400"}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({bad}, &w).fps == 0);
    CHECK(w.rfind("glbudget: GLBUDGET_FPS=", 0) == 0);
    CHECK(std::count(w.begin(), w.end(), '\n') == 1);
  }
}

TEST_CASE("unknown GLBUDGET_ variables are named; others are ignored", "[unit]") {
  std::string w;
  Options o = parse_env(
      {"GLBUDGET_LOG=/tmp/x.csv", "GLBUDGET_LGO=/tmp/y.csv", "HOME=/root", "GLBUDGET", "GLBUDGET_POWER=40%"}, &w);
  CHECK(o.log_path == "/tmp/x.csv");
  CHECK(w == "glbudget: unknown variable GLBUDGET_LGO ignored\n");
}

TEST_CASE("every variable of the README's options table is one the shim knows", "[unit]") {
  // A variable missing from the shim's list is said to be unknown and ignored: the option a
  // user sets (or a study's A/B switch) would silently do nothing.
  std::ifstream readme(GLBUDGET_README);
  REQUIRE(readme);
  const std::regex name("GLBUDGET_[A-Z0-9_]+");
  int checked = 0;
  for (std::string line; std::getline(readme, line);) {
    if (line.rfind("| `GLBUDGET_", 0) != 0) continue;
    const std::string first_cell = line.substr(0, line.find(" | ", 2));
    for (std::sregex_iterator it(first_cell.begin(), first_cell.end(), name), end; it != end; ++it) {
      std::string w;
      parse_env({it->str() + "="}, &w);
      INFO(it->str() << ": " << w);
      CHECK(w.find("unknown variable") == std::string::npos);
      ++checked;
    }
  }
  CHECK(checked >= 15);  // the table names 18 today
}

TEST_CASE("frame-log rows: empty fields for what was not measured", "[unit]") {
  char line[256];
  FrameRow r;
  r.frame = 7;
  r.time_ns = 123456789;
  r.context = 1;
  r.pass = 0x00ab00cd00ef0012ull;
  r.batches = 20000;
  r.vertices = 60000;
  r.fragments = 0;
  r.primitives = 20000;
  r.gpu_ns = -1;
  format_row(r, line, sizeof line);
  CHECK(std::string(line) == "7,123456789,1,00ab00cd00ef0012,20000,60000,0,20000,,,,,0,,,,,,,,");
  r.configuration = "2:0:1";  // the levels that drew the frame, last
  format_row(r, line, sizeof line);
  CHECK(std::string(line) == "7,123456789,1,00ab00cd00ef0012,20000,60000,0,20000,,,,,0,2:0:1,,,,,,,");
  // The governor's view of the frame: predicted power, budget, estimated error, decision.
  r.predicted_w = 21.5;
  r.budget_w = 24.0;
  r.est_error = 0.004;
  r.decision = "select";
  format_row(r, line, sizeof line);
  CHECK(std::string(line) ==
        "7,123456789,1,00ab00cd00ef0012,20000,60000,0,20000,,,,,0,2:0:1,21.5000,24.0000,0.004000,select,,,");
  r.predicted_w = NAN;  // before the first fit
  format_row(r, line, sizeof line);
  CHECK(std::string(line) ==
        "7,123456789,1,00ab00cd00ef0012,20000,60000,0,20000,,,,,0,2:0:1,,24.0000,0.004000,select,,,");
  // A probe frame: flagged, with the shown frame's measured error once known.
  r.probe = true;
  format_row(r, line, sizeof line);
  CHECK(std::string(line) ==
        "7,123456789,1,00ab00cd00ef0012,20000,60000,0,20000,,,,,0,2:0:1,,24.0000,0.004000,select,1,,");
  r.probe_error = 0.0125;
  format_row(r, line, sizeof line);
  CHECK(std::string(line) ==
        "7,123456789,1,00ab00cd00ef0012,20000,60000,0,20000,,,,,0,2:0:1,,24.0000,0.004000,select,1,0.012500,");
  r.probe_streams = "0:0:2=0.031000";  // each stream but the best's, against the best
  format_row(r, line, sizeof line);
  CHECK(std::string(line) ==
        "7,123456789,1,00ab00cd00ef0012,20000,60000,0,20000,,,,,0,2:0:1,,24.0000,0.004000,select,1,0.012500,"
        "0:0:2=0.031000");
  FrameRow ff;
  ff.pass = kFixedFunctionPass;
  format_row(ff, line, sizeof line);
  CHECK(std::string(line) == "0,0,0,fixed-function,0,,,,,,,,0,,,,,,,,");
  // With a sensor: power, energy, the sensor's name (estimates labelled), dropped samples.
  FrameRow powered;
  powered.energy.valid = true;
  powered.energy.energy_j = 0.25;
  powered.energy.mean_power_w = 15.0;
  powered.energy.sensor = "cpu";
  powered.energy.estimate = true;
  powered.energy.dropped_samples = 2;
  format_row(powered, line, sizeof line);
  CHECK(std::string(line).find("0,0,0,fixed-function,0,,,,,15") == 0);
  CHECK(std::string(line).find(",cpu~estimate,2") != std::string::npos);
  // Extremes: the largest counts fit the line.
  FrameRow big;
  big.frame = UINT64_MAX;
  big.time_ns = INT64_MAX;
  big.batches = UINT64_MAX;
  big.vertices = big.fragments = big.primitives = big.gpu_ns = INT64_MAX;
  big.pass = UINT64_MAX;
  int n = format_row(big, line, sizeof line);
  CHECK(n < int(sizeof line));
  CHECK(std::string(line).find("18446744073709551615,9223372036854775807,0,ffffffffffffffff,18446744073709551615") ==
        0);
}

TEST_CASE("GLBUDGET_TEST_HIDE_EXTENSIONS: a comma-separated list of extensions, spaces trimmed", "[unit]") {
  std::string w;
  Options o = parse_env({"GLBUDGET_TEST_HIDE_EXTENSIONS=GL_ARB_timer_query, GL_ARB_pipeline_statistics_query,,"}, &w);
  CHECK(w.empty());  // a known variable
  CHECK(o.hide_extensions == std::vector<std::string>{"GL_ARB_timer_query", "GL_ARB_pipeline_statistics_query"});
  CHECK(parse_env({"GLBUDGET_TEST_HIDE_EXTENSIONS="}, &w).hide_extensions.empty());
  CHECK(parse_env({}, &w).hide_extensions.empty());
}

TEST_CASE("GLBUDGET_TEST_OUT_OF_MEMORY: pass:level items; others said and ignored", "[unit]") {
  std::string w;
  Options o = parse_env({"GLBUDGET_TEST_OUT_OF_MEMORY=fragile:2,,a:b:0"}, &w);
  CHECK(w.empty());
  CHECK(o.test_out_of_memory == std::vector<std::pair<std::string, size_t>>{{"fragile", 2}, {"a:b", 0}});
  o = parse_env({"GLBUDGET_TEST_OUT_OF_MEMORY=nolevel,:3,x:,x:1y,ok:1"}, &w);
  CHECK(o.test_out_of_memory == std::vector<std::pair<std::string, size_t>>{{"ok", 1}});
  for (const char* bad : {"'nolevel'", "':3'", "'x:'", "'x:1y'"})
    CHECK(w.find(std::string("GLBUDGET_TEST_OUT_OF_MEMORY item ") + bad + " is not pass:level; ignored") !=
          std::string::npos);
  CHECK(parse_env({"GLBUDGET_TEST_OUT_OF_MEMORY="}, &w).test_out_of_memory.empty());
}

TEST_CASE("GLBUDGET_TEST_MEASURE_DELAY_MS: milliseconds up to a minute; others said and ignored", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).test_measure_delay_ms == 0);
  CHECK(parse_env({"GLBUDGET_TEST_MEASURE_DELAY_MS=0"}, &w).test_measure_delay_ms == 0);
  CHECK(parse_env({"GLBUDGET_TEST_MEASURE_DELAY_MS=60000"}, &w).test_measure_delay_ms == 60000);
  CHECK(w.empty());
  for (const char* bad : {"-1", "60001", "5ms", "", "1e3"}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({std::string("GLBUDGET_TEST_MEASURE_DELAY_MS=") + bad}, &w).test_measure_delay_ms == 0);
    CHECK(w.find(std::string("GLBUDGET_TEST_MEASURE_DELAY_MS='") + bad + "' is not milliseconds") != std::string::npos);
  }
}

TEST_CASE("GLBUDGET_PROBE_SSIM: auto, gpu or cpu; anything else said once, auto", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).probe_ssim == Options::ProbeSsim::kAuto);
  CHECK(parse_env({"GLBUDGET_PROBE_SSIM=auto"}, &w).probe_ssim == Options::ProbeSsim::kAuto);
  CHECK(parse_env({"GLBUDGET_PROBE_SSIM=gpu"}, &w).probe_ssim == Options::ProbeSsim::kGpu);
  CHECK(parse_env({"GLBUDGET_PROBE_SSIM=cpu"}, &w).probe_ssim == Options::ProbeSsim::kCpu);
  CHECK(w.empty());
  for (const char* bad : {"GLBUDGET_PROBE_SSIM=", "GLBUDGET_PROBE_SSIM=GPU", "GLBUDGET_PROBE_SSIM=gpu "}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({bad}, &w).probe_ssim == Options::ProbeSsim::kAuto);
    CHECK(w.rfind("glbudget: GLBUDGET_PROBE_SSIM=", 0) == 0);
    CHECK(std::count(w.begin(), w.end(), '\n') == 1);
  }
}

TEST_CASE("GLBUDGET_PROBE_STRETCH: on unless 0 or off; anything else said once, on", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).probe_stretch);
  CHECK(parse_env({"GLBUDGET_PROBE_STRETCH=1"}, &w).probe_stretch);
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_STRETCH=0"}, &w).probe_stretch);
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_STRETCH=off"}, &w).probe_stretch);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_PROBE_STRETCH=rare"}, &w).probe_stretch);
  CHECK(w == "glbudget: GLBUDGET_PROBE_STRETCH='rare' is not 0/1/on/off; on\n");
}

TEST_CASE("GLBUDGET_EXPLORE_HELD: on unless 0 or off; anything else said once, on", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).explore_held);
  CHECK(parse_env({"GLBUDGET_EXPLORE_HELD=on"}, &w).explore_held);
  CHECK_FALSE(parse_env({"GLBUDGET_EXPLORE_HELD=0"}, &w).explore_held);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_EXPLORE_HELD=sometimes"}, &w).explore_held);
  CHECK(w == "glbudget: GLBUDGET_EXPLORE_HELD='sometimes' is not 0/1/on/off; on\n");
}

TEST_CASE("GLBUDGET_TRANSITION_ORDER: on unless 0 or off; anything else said once, on", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).transition_order);
  CHECK(parse_env({"GLBUDGET_TRANSITION_ORDER=1"}, &w).transition_order);
  CHECK_FALSE(parse_env({"GLBUDGET_TRANSITION_ORDER=off"}, &w).transition_order);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_TRANSITION_ORDER=cheapest"}, &w).transition_order);
  CHECK(w == "glbudget: GLBUDGET_TRANSITION_ORDER='cheapest' is not 0/1/on/off; on\n");
}

TEST_CASE("GLBUDGET_MEASURED_AT_WINDOWS: off unless 1 or on; anything else said once, off", "[unit]") {
  std::string w;
  CHECK_FALSE(parse_env({}, &w).measured_at_windows);
  CHECK(parse_env({"GLBUDGET_MEASURED_AT_WINDOWS=1"}, &w).measured_at_windows);
  CHECK_FALSE(parse_env({"GLBUDGET_MEASURED_AT_WINDOWS=off"}, &w).measured_at_windows);
  CHECK(w.empty());
  CHECK_FALSE(parse_env({"GLBUDGET_MEASURED_AT_WINDOWS=often"}, &w).measured_at_windows);
  CHECK(w == "glbudget: GLBUDGET_MEASURED_AT_WINDOWS='often' is not 0/1/on/off; off\n");
}

TEST_CASE("GLBUDGET_BEST_BAND: a share in [0, 1] or off; anything else said once, 0.1", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).best_band == 0.1);
  CHECK(parse_env({"GLBUDGET_BEST_BAND=0"}, &w).best_band == 0.0);
  CHECK(parse_env({"GLBUDGET_BEST_BAND=25%"}, &w).best_band == Approx(0.25));
  CHECK(parse_env({"GLBUDGET_BEST_BAND=1"}, &w).best_band == 1.0);
  CHECK(std::isinf(parse_env({"GLBUDGET_BEST_BAND=off"}, &w).best_band));
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_BEST_BAND=1.5"}, &w).best_band == 0.1);
  CHECK(w == "glbudget: GLBUDGET_BEST_BAND='1.5' is not a share in [0, 1] (0.1 or 10%) or off; 0.1\n");
  w.clear();
  CHECK(parse_env({"GLBUDGET_BEST_BAND=wide"}, &w).best_band == 0.1);
  CHECK(w == "glbudget: GLBUDGET_BEST_BAND='wide' is not a share in [0, 1] (0.1 or 10%) or off; 0.1\n");
}

TEST_CASE("GLBUDGET_REMEMBER_FRAMES: frames in [0, 100000]; anything else said once, the model's", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).remember_frames == -1);
  CHECK(parse_env({"GLBUDGET_REMEMBER_FRAMES=0"}, &w).remember_frames == 0);
  CHECK(parse_env({"GLBUDGET_REMEMBER_FRAMES=100000"}, &w).remember_frames == 100000);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_REMEMBER_FRAMES=100001"}, &w).remember_frames == -1);
  CHECK(w ==
        "glbudget: GLBUDGET_REMEMBER_FRAMES='100001' is not a number of frames in [0, 100000]; the model's default\n");
  w.clear();
  CHECK(parse_env({"GLBUDGET_REMEMBER_FRAMES=-3"}, &w).remember_frames == -1);
  CHECK(w == "glbudget: GLBUDGET_REMEMBER_FRAMES='-3' is not a number of frames in [0, 100000]; the model's default\n");
}

TEST_CASE("GLBUDGET_METER_WINDOWS: on unless 0 or off; anything else said once, on", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).meter_windows);
  CHECK(parse_env({"GLBUDGET_METER_WINDOWS=on"}, &w).meter_windows);
  CHECK_FALSE(parse_env({"GLBUDGET_METER_WINDOWS=0"}, &w).meter_windows);
  CHECK_FALSE(parse_env({"GLBUDGET_METER_WINDOWS=off"}, &w).meter_windows);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_METER_WINDOWS=always"}, &w).meter_windows);
  CHECK(w == "glbudget: GLBUDGET_METER_WINDOWS='always' is not 0/1/on/off; on\n");
}

TEST_CASE("GLBUDGET_PROBE_FOLLOW: on unless 0 or off; anything else said once, on", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).probe_follow);
  CHECK(parse_env({"GLBUDGET_PROBE_FOLLOW=1"}, &w).probe_follow);
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_FOLLOW=0"}, &w).probe_follow);
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_FOLLOW=off"}, &w).probe_follow);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_PROBE_FOLLOW=lead"}, &w).probe_follow);
  CHECK(w == "glbudget: GLBUDGET_PROBE_FOLLOW='lead' is not 0/1/on/off; on\n");
}

TEST_CASE("GLBUDGET_PROBE_SWEEP: on unless 0 or off; anything else said once, on", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).probe_sweep);
  CHECK_FALSE(parse_env({}, &w).probe_sweep_set);
  CHECK(parse_env({"GLBUDGET_PROBE_SWEEP=1"}, &w).probe_sweep);
  CHECK(parse_env({"GLBUDGET_PROBE_SWEEP=1"}, &w).probe_sweep_set);
  CHECK(parse_env({"GLBUDGET_PROBE_SWEEP=on"}, &w).probe_sweep);
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_SWEEP=0"}, &w).probe_sweep);
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_SWEEP=off"}, &w).probe_sweep);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_PROBE_SWEEP=all"}, &w).probe_sweep);
  CHECK(w == "glbudget: GLBUDGET_PROBE_SWEEP='all' is not 0/1/on/off; on\n");
}

TEST_CASE("GLBUDGET_PROBE_PASSES: 1 to 64 passes a probe frame; others said, as many as fit", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).probe_passes == 0);
  CHECK(parse_env({"GLBUDGET_PROBE_PASSES=1"}, &w).probe_passes == 1);
  CHECK(parse_env({"GLBUDGET_PROBE_PASSES=64"}, &w).probe_passes == 64);
  CHECK(w.empty());
  for (const char* bad : {"0", "65", "-1", "2.5", "", "all"}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({std::string("GLBUDGET_PROBE_PASSES=") + bad}, &w).probe_passes == 0);
    CHECK(w == std::string("glbudget: GLBUDGET_PROBE_PASSES='") + bad +
                   "' is not a number of passes in [1, 64]; as many as fit\n");
  }
}

TEST_CASE("GLBUDGET_PROBE_MAX_AGE_S and GLBUDGET_TRANSITION_S: seconds up to an hour; others said, the default",
          "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).probe_max_age_s == 10.0);
  CHECK(parse_env({"GLBUDGET_PROBE_MAX_AGE_S=0"}, &w).probe_max_age_s == 0.0);
  CHECK(parse_env({"GLBUDGET_PROBE_MAX_AGE_S=2.5"}, &w).probe_max_age_s == 2.5);
  CHECK(parse_env({"GLBUDGET_PROBE_MAX_AGE_S=3600"}, &w).probe_max_age_s == 3600.0);
  CHECK(parse_env({"GLBUDGET_TRANSITION_S=0.5"}, &w).transition_s == 0.5);
  CHECK(w.empty());
  for (const char* bad : {"-1", "3601", "5s", "", "nan", "inf"}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({std::string("GLBUDGET_PROBE_MAX_AGE_S=") + bad}, &w).probe_max_age_s == 10.0);
    CHECK(w == std::string("glbudget: GLBUDGET_PROBE_MAX_AGE_S='") + bad +
                   "' is not a number of seconds in [0, 3600]; 10\n");
    w.clear();
    CHECK(parse_env({std::string("GLBUDGET_TRANSITION_S=") + bad}, &w).transition_s == 2.0);
    CHECK(w ==
          std::string("glbudget: GLBUDGET_TRANSITION_S='") + bad + "' is not a number of seconds in [0, 3600]; 2\n");
  }
}

TEST_CASE("GLBUDGET_KEEP_SHARE: a share of windows in [0.5, 0.999], as a fraction or a percentage; 0.98", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).keep_share == 0.98);
  CHECK(parse_env({"GLBUDGET_KEEP_SHARE=0.95"}, &w).keep_share == 0.95);
  CHECK(parse_env({"GLBUDGET_KEEP_SHARE=99%"}, &w).keep_share == Approx(0.99));
  CHECK(parse_env({"GLBUDGET_KEEP_SHARE=0.5"}, &w).keep_share == 0.5);
  CHECK(parse_env({"GLBUDGET_KEEP_SHARE=0.999"}, &w).keep_share == 0.999);
  CHECK(w.empty());
  for (const char* bad : {"0.49", "1", "100%", "0.98x", "%", "", "nan", "-0.9", "98%%"}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({std::string("GLBUDGET_KEEP_SHARE=") + bad}, &w).keep_share == 0.98);
    CHECK(w == std::string("glbudget: GLBUDGET_KEEP_SHARE='") + bad +
                   "' is not a share in [0.5, 0.999] (0.98 or 98%); 0.98\n");
  }
}

TEST_CASE("GLBUDGET_SURPRISE_FLOOR: a share in [0, 0.5], as a fraction or a percentage, or off; 0.02 by default",
          "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).surprise_floor == 0.02);
  CHECK(parse_env({"GLBUDGET_SURPRISE_FLOOR=0.05"}, &w).surprise_floor == 0.05);
  CHECK(parse_env({"GLBUDGET_SURPRISE_FLOOR=3%"}, &w).surprise_floor == Approx(0.03));
  CHECK(parse_env({"GLBUDGET_SURPRISE_FLOOR=0"}, &w).surprise_floor == 0.0);
  CHECK(parse_env({"GLBUDGET_SURPRISE_FLOOR=off"}, &w).surprise_floor == 0.0);
  CHECK(w.empty());
  for (const char* bad : {"-0.1", "0.6", "51%", "x", "", "nan", "inf"}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({std::string("GLBUDGET_SURPRISE_FLOOR=") + bad}, &w).surprise_floor == 0.02);
    CHECK(w == std::string("glbudget: GLBUDGET_SURPRISE_FLOOR='") + bad +
                   "' is not a share in [0, 0.5] (0.02 or 2%) or off; the default, 0.02\n");
  }
}

TEST_CASE("GLBUDGET_FIRST_SAVING_DISCOUNT: a share in [0, 0.9], as a fraction or a percentage; 0", "[unit]") {
  std::string w;
  CHECK(parse_env({}, &w).first_saving_discount == 0.0);
  CHECK(parse_env({"GLBUDGET_FIRST_SAVING_DISCOUNT=0.25"}, &w).first_saving_discount == 0.25);
  CHECK(parse_env({"GLBUDGET_FIRST_SAVING_DISCOUNT=0.9"}, &w).first_saving_discount == 0.9);
  CHECK(parse_env({"GLBUDGET_FIRST_SAVING_DISCOUNT=40%"}, &w).first_saving_discount == Approx(0.4));
  CHECK(w.empty());
  for (const char* bad : {"-0.1", "1", "0.95", "91%", "x", "", "nan", "inf"}) {
    INFO(bad);
    w.clear();
    CHECK(parse_env({std::string("GLBUDGET_FIRST_SAVING_DISCOUNT=") + bad}, &w).first_saving_discount == 0.0);
    CHECK(w == std::string("glbudget: GLBUDGET_FIRST_SAVING_DISCOUNT='") + bad +
                   "' is not a share in [0, 0.9] (0.25 or 25%); 0\n");
  }
}

TEST_CASE("GLBUDGET_PROBE_LEVELS: cheapest or all; anything else said once, cheapest", "[unit]") {
  std::string w;
  CHECK_FALSE(parse_env({}, &w).probe_every_level);
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_LEVELS=cheapest"}, &w).probe_every_level);
  CHECK(parse_env({"GLBUDGET_PROBE_LEVELS=all"}, &w).probe_every_level);
  CHECK(w.empty());
  CHECK_FALSE(parse_env({"GLBUDGET_PROBE_LEVELS=every"}, &w).probe_every_level);
  CHECK(w == "glbudget: GLBUDGET_PROBE_LEVELS='every' is not cheapest or all; cheapest\n");
}

TEST_CASE("GLBUDGET_PROBE_SSIM and GLBUDGET_LEVEL_INTERACTIONS: one of their names; anything else said, the default",
          "[unit]") {
  std::string w;
  using S = Options::ProbeSsim;
  using L = loop::LevelInteractions;
  CHECK(parse_env({}, &w).probe_ssim == S::kAuto);
  CHECK(parse_env({"GLBUDGET_PROBE_SSIM=gpu"}, &w).probe_ssim == S::kGpu);
  CHECK(parse_env({"GLBUDGET_PROBE_SSIM=cpu"}, &w).probe_ssim == S::kCpu);
  CHECK(parse_env({}, &w).level_interactions == L::scaled);
  CHECK(parse_env({"GLBUDGET_LEVEL_INTERACTIONS=calibrated"}, &w).level_interactions == L::calibrated);
  CHECK(parse_env({"GLBUDGET_LEVEL_INTERACTIONS=additive"}, &w).level_interactions == L::additive);
  CHECK(parse_env({"GLBUDGET_LEVEL_INTERACTIONS=model"}, &w).level_interactions == L::model);
  CHECK(parse_env({"GLBUDGET_LEVEL_INTERACTIONS=scaled"}, &w).level_interactions == L::scaled);
  CHECK(w.empty());
  CHECK(parse_env({"GLBUDGET_PROBE_SSIM=fpga"}, &w).probe_ssim == S::kAuto);
  CHECK(w == "glbudget: GLBUDGET_PROBE_SSIM='fpga' is not auto, gpu or cpu; auto\n");
  w.clear();
  CHECK(parse_env({"GLBUDGET_LEVEL_INTERACTIONS=Model"}, &w).level_interactions == L::scaled);
  CHECK(w == "glbudget: GLBUDGET_LEVEL_INTERACTIONS='Model' is not calibrated, additive, model or scaled; scaled\n");
}
