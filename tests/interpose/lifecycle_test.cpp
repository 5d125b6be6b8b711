// Integration: the shim in processes that never draw, bad variables, every way of ending a
// process, fork without exec, and frame pacing.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <sstream>

#include "probe_expectations.hpp"

namespace {
size_t data_rows(const std::string& log) {
  auto rows = read_csv(log);
  return rows.empty() ? 0 : rows.size() - 1;
}

}  // namespace

TEST_CASE("processes that never make a context current run exactly as without the shim", "[integration]") {
  std::string log = temp_path("inert.csv");
  for (std::vector<std::string> cmd : {std::vector<std::string>{"sh", "-c", "echo hello; ls / >/dev/null; exit 3"},
                                       std::vector<std::string>{"python3", "-c", "import ctypes; print(6*7)"}}) {
    auto plain = run_process(cmd, {});
    auto shim = run_process(cmd, {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}, {"GLBUDGET_FPS", "bogus"}});
    CHECK(shim.exit_code == plain.exit_code);
    CHECK(shim.out == plain.out);
    CHECK(shim.err == plain.err);  // not even the warning for the bad variable: no GL, no word
  }
  CHECK(!file_exists(log));
}

TEST_CASE("bad variables: one glbudget: line each, defaults, the app runs on", "[integration]") {
  std::string log = temp_path("badenv.csv");
  unlink(log.c_str());
  std::string img = temp_path("badenv.ppm");
  auto r = run_process({probe_path("probe_direct"), "--frames", "4", "--out", img}, {{"LD_PRELOAD", shim_path()},
                                                                                     {"GLBUDGET_LOG", log},
                                                                                     {"GLBUDGET_FPS", "fast"},
                                                                                     {"GLBUDGET_FRAMERATE", "30"},
                                                                                     {"GLBUDGET_SENSOR", "cpu"}});
  CHECK(r.exit_code == 0);
  CHECK(count_lines_with(r.err, "glbudget:") == 2);
  CHECK(count_lines_with(r.err, "glbudget: GLBUDGET_FPS='fast'") == 1);
  CHECK(count_lines_with(r.err, "glbudget: unknown variable GLBUDGET_FRAMERATE") == 1);
  CHECK(data_rows(log) == 8);

  // A log path that cannot be written: one message, the app unchanged.
  r = run_process({probe_path("probe_direct"), "--frames", "4"},
                  {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", "/nonexistent-dir/x.csv"}});
  CHECK(r.exit_code == 0);
  CHECK(count_lines_with(r.err, "glbudget: cannot write GLBUDGET_LOG file '/nonexistent-dir/x.csv'") == 1);
}

TEST_CASE("the log is complete however the process ends", "[integration]") {
  for (std::string mode : {"normal", "_exit", "sigterm"}) {
    INFO("exit mode " << mode);
    std::string log = temp_path("exit_" + mode + ".csv");
    unlink(log.c_str());
    std::vector<std::string> cmd = {probe_path("probe_lifecycle"), "--frames", "5", "--exit", mode};
    auto plain = run_process(cmd, {});
    auto shim = run_process(cmd, {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}});
    CHECK(shim.exit_code == plain.exit_code);
    if (mode == "sigterm") CHECK(shim.exit_code == 128 + SIGTERM);
    // Five frames of two passes. On SIGTERM, frames still awaiting GPU results (at most the
    // last) cannot be read from a signal handler; every earlier one must be there.
    if (mode == "sigterm")
      CHECK(data_rows(log) >= 8);
    else
      CHECK(data_rows(log) == 10);
  }
}

TEST_CASE("fork without exec: a child that renders gets its own log, one that does not gets none", "[integration]") {
  std::string log = temp_path("fork.csv");
  unlink(log.c_str());
  auto r = run_process({probe_path("probe_lifecycle"), "--frames", "4", "--fork"},
                       {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}});
  REQUIRE(r.exit_code == 0);
  std::istringstream out(r.out);
  std::string word;
  int renderer = 0, idle = 0;
  out >> word >> renderer >> word >> idle;
  REQUIRE(renderer > 0);
  REQUIRE(idle > 0);
  CHECK(data_rows(log) == 8);  // the parent's 4 frames
  std::string base = log.substr(0, log.rfind('.'));
  std::string renderer_log = base + "." + std::to_string(renderer) + ".csv";
  std::string idle_log = base + "." + std::to_string(idle) + ".csv";
  CHECK(data_rows(renderer_log) == 6);  // the child's own 3 frames
  CHECK(!file_exists(idle_log));
  unlink(renderer_log.c_str());
}

// A child forked after the governor started has no governor thread: stopped by SIGINT (as
// Ctrl-C stops a whole process group) it must not wait for one to log its frames (the
// shim's handler waits up to 2 s for the parent's).
TEST_CASE("fork without exec under the governor: the child stopped by SIGINT ends at once", "[integration]") {
  std::string log = temp_path("fork_interrupted.csv");
  unlink(log.c_str());
  auto r = run_process(
      {probe_path("probe_lifecycle"), "--frames", "6", "--fork-interrupted"},
      {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}, {"GLBUDGET_SENSOR", "cpu"}, {"GLBUDGET_PROBE_PERIOD", "2"}});
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  long ms = -1;
  std::sscanf(r.out.c_str() + std::min(r.out.size(), r.out.find("child interrupted after ")),
              "child interrupted after %ld ms", &ms);
  REQUIRE(ms >= 0);
  CHECK(ms < 1000);
  CHECK(data_rows(log) >= 6);  // the parent's frames, logged at its exit
  unlink(log.c_str());
}

TEST_CASE("GLBUDGET_FPS paces the swaps", "[integration]") {
  std::string log = temp_path("fps.csv");
  unlink(log.c_str());
  auto start = std::chrono::steady_clock::now();
  auto r = run_process({probe_path("probe_direct"), "--frames", "6"},
                       {{"LD_PRELOAD", shim_path()}, {"GLBUDGET_LOG", log}, {"GLBUDGET_FPS", "20"}});
  double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  REQUIRE(r.exit_code == 0);
  // Six swaps at 20 fps: five full periods of 50 ms at least between the first and the last.
  CHECK(seconds >= 0.25);
  auto rows = read_csv(log);
  REQUIRE(rows.size() == 13);
  std::vector<long long> swaps;
  for (size_t i = 1; i < rows.size(); i += 2) swaps.push_back(std::stoll(rows[i][1]));
  // The cadence is kept on average: a late frame is not followed by a sleep (catch-up), so
  // single intervals may be shorter, but five of them span at least five periods.
  CHECK(swaps.back() - swaps.front() >= 5 * 50'000'000 - 1'000'000);
}
