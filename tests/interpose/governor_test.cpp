// Integration (issue 13): the governor keeps a running app under a power budget. The demo and
// glmark2 under GLBUDGET_POWER with the cpu sensor's estimate (this machine's only source):
// the loop fits, selects and moves to a cheaper configuration, and power drops.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "probe_expectations.hpp"
#include "xvfb_server.hpp"

namespace {

std::string source(const std::string& path) { return std::string(GLBUDGET_SOURCE_DIR) + "/" + path; }
const std::string kProfile = source("tests/data/logs/demo_cpu.profile.json");

struct Frames {
  std::map<long, double> power;      // per frame
  std::map<long, double> fragments;  // all passes' fragment-shader invocations
  std::map<long, std::string> configuration;
  std::map<long, std::string> decision;
  std::map<long, double> budget;
};

Frames frames_of(const std::string& log) {
  Frames f;
  for (const auto& row : read_csv_rows_by_name(log)) {
    const long frame = std::stol(row.at("frame"));
    if (!row.at("power_w").empty()) f.power[frame] = std::stod(row.at("power_w"));
    if (!row.at("fragments").empty()) f.fragments[frame] += std::stod(row.at("fragments"));
    f.configuration[frame] = row.at("configuration");
    f.decision[frame] = row.at("decision");
    if (!row.at("budget_w").empty()) f.budget[frame] = std::stod(row.at("budget_w"));
  }
  return f;
}

double mean_of(const std::map<long, double>& by_frame, long from, long to) {
  double sum = 0;
  int n = 0;
  for (auto& [frame, v] : by_frame)
    if (frame >= from && frame <= to) sum += v, ++n;
  return n ? sum / n : NAN;
}
double mean_power(const Frames& f, long from, long to) { return mean_of(f.power, from, to); }

}  // namespace

TEST_CASE("the demo under a 40 % budget: fit, select, transition, and the power falls", "[integration]") {
  const std::string log = temp_path("governed.csv");
  unlink(log.c_str());
  const ProcessResult r = run_process(
      {DEMO_PATH, "--scene", "hall", "--detail", "0.2", "--width", "320", "--height", "180", "--frames", "160"},
      {{"LD_PRELOAD", shim_path()},
       {"GLBUDGET_CONFIG", source("testapps/demo/glbudget.toml")},
       {"GLBUDGET_POWER", "40%"},
       {"GLBUDGET_PROFILE", kProfile},
       {"GLBUDGET_SENSOR", "cpu"},
       {"GLBUDGET_FPS", "10"},
       {"GLBUDGET_SELECT_FRAMES", "60"},
       {"GLBUDGET_TRANSITION_S", "1"},
       {"GLBUDGET_LOG", log}});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  const Frames f = frames_of(log);
  std::set<std::string> decisions;
  for (auto& [frame, d] : f.decision) decisions.insert(d);
  CHECK(decisions.count("fit") + decisions.count("select") >= 1);
  CHECK(decisions.count("select") == 1);
  CHECK(decisions.count("transition") == 1);
  // The fitter keeps learning after its fit: it checks the model every 10 usable frames, and a
  // changed configuration starts a new 30-frame fitting window (probe frames and those after
  // them are not usable). The decision column holds one event a frame, a selection's over a
  // check's, so the check is asserted where the run gives the fitter room: every steady stretch
  // of 45 frames or more (no configuration change or transition) holds a check or a
  // refit. The governor reselects whenever the configuration it chose is predicted over the
  // budget, more often where the shim runs sanitized (its extra CPU time reads as power), so a
  // run may have no such stretch; it is said, not failed.
  const long first_fit = [&] {
    for (auto& [frame, d] : f.decision)
      if (d == "fit") return frame;
    return 0L;
  }();
  REQUIRE(first_fit > 0);
  long stretch_start = 0, longest_stretch = 0;
  bool learnt = false;
  auto close_stretch = [&](long end) {
    if (stretch_start > 0 && end - stretch_start >= 45) {
      INFO("frames " << stretch_start << "-" << end - 1 << " at " << f.configuration.at(stretch_start));
      CHECK(learnt);
    }
    if (stretch_start > 0) longest_stretch = std::max(longest_stretch, end - stretch_start);
    stretch_start = 0;
  };
  std::string previous_configuration;
  for (auto& [frame, d] : f.decision) {
    if (frame <= first_fit) continue;
    const std::string& c = f.configuration.at(frame);
    const bool moved = d == "transition" || c != previous_configuration;  // a selection may keep it
    previous_configuration = c;
    if (moved) {
      close_stretch(frame);
      continue;
    }
    if (stretch_start == 0) stretch_start = frame, learnt = false;
    learnt = learnt || d == "check" || d == "refit";
  }
  close_stretch(f.decision.rbegin()->first + 1);
  if (longest_stretch < 45)
    WARN("no steady stretch of 45 frames after the fit (longest " << longest_stretch << "): checks not asserted");
  // Best until the model is fitted (30 frames), then cheaper.
  CHECK(f.configuration.at(10) == "0:0:0:0:0:0");
  CHECK(f.configuration.rbegin()->second != "0:0:0:0:0:0");
  CHECK(!f.budget.empty());
  // What the configuration draws is what the governor controls; the power it then measures is
  // the cpu sensor's estimate from the process's share of the CPU, which anything else running
  // on this 2-core machine moves by more than the knobs do (a run beside a build measured more
  // power under the budget than before it). So the test asserts the loop, and reports the
  // power; bench/governor/evaluate_budgets.py measures budgets kept on a quiet machine.
  const double work_before = mean_of(f.fragments, 5, 30), work_after = mean_of(f.fragments, 130, 160);
  const double before = mean_power(f, 5, 30), after = mean_power(f, 130, 160);
  WARN("fragments per frame " << work_before << " then " << work_after << "; mean power before the first "
                              << "selection " << before << " W, at the end " << after << " W (estimate)");
  unlink(log.c_str());
}

// Under an error budget the governor corrects its estimates by what each probe measures of the
// image shown (governor/loop/error_feedback.hpp), and a probe that measures the settled
// configuration over the budget selects again at once. With selections otherwise never due
// again after the first (GLBUDGET_SELECT_FRAMES), every later selection is one such a probe
// asked for.
TEST_CASE("under an error budget, the probes' error of the image shown corrects the estimate", "[integration]") {
  constexpr double kBudget = 0.01;
  struct Row {
    std::string configuration, decision;
    double est_error = -1.0;
    double probe_error = -1.0;  // -1: not a probe frame
  };
  auto run = [&](const std::string& name, const char* feedback) {
    const std::string log = temp_path(name);
    unlink(log.c_str());
    const std::vector<std::string> argv = {DEMO_PATH, "--scene",  "subway", "--detail", "0.2", "--width",
                                           "320",     "--height", "180",    "--frames", "240"};
    const std::map<std::string, std::string> env = {
        {"LD_PRELOAD", shim_path()},
        {"GLBUDGET_CONFIG", source("testapps/demo/glbudget.toml")},
        // The levels' costs, so that the power the selection weighs does not hang on one fit
        // of the cpu estimate (a fit that saw no saving keeps the best configuration).
        {"GLBUDGET_COSTS", source("tests/data/logs/demo_subway.variants.json")},
        {"GLBUDGET_ERROR", std::to_string(kBudget)},
        {"GLBUDGET_PROFILE", kProfile},
        {"GLBUDGET_SENSOR", "cpu"},
        {"GLBUDGET_FPS", "20"},
        {"GLBUDGET_PROBE_PERIOD", "5"},
        {"GLBUDGET_SELECT_FRAMES", "100000"},
        {"GLBUDGET_TRANSITION_S", "0.5"},
        {"GLBUDGET_ERROR_FEEDBACK", feedback},
        {"GLBUDGET_LOG", log}};
    ProcessResult r = run_process(argv, env);
    // This run has died of llvmpipe's fence race now and then (Mesa 22.3: a rasterizer thread
    // unlocks a fence the demo's own draw has freed; the heap is corrupted, the shim on neither
    // stack; README, "Seen and not understood"). Such a run is run once more, and says so.
    if (r.exit_code == 128 + 11 || r.exit_code == 128 + 6) {
      WARN(name << " died of signal " << r.exit_code - 128 << "; run again");
      unlink(log.c_str());
      r = run_process(argv, env);
    }
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    std::map<long, Row> rows;
    for (const auto& row : read_csv_rows_by_name(log)) {
      Row& f = rows[std::stol(row.at("frame"))];
      f.configuration = row.at("configuration");
      f.decision = row.at("decision");
      if (!row.at("est_error").empty()) f.est_error = std::stod(row.at("est_error"));
      if (!row.at("probe_error").empty()) f.probe_error = std::stod(row.at("probe_error"));
    }
    unlink(log.c_str());
    return rows;
  };
  auto selections = [](const std::map<long, Row>& rows) {
    std::vector<long> at;
    for (const auto& [frame, row] : rows)
      if (row.decision == "select") at.push_back(frame);
    return at;
  };
  const std::string best = "0:0:0:0:0:0";

  // Without the correction, one selection. Its paths are a subset of the corrected run's, so the
  // sanitizer trees, where each run takes minutes, leave it to the plain build.
  if (!kSanitizedRun) {
    const std::map<long, Row> open = run("error_feedback_off.csv", "0");
    CHECK(selections(open).size() == 1);
  }

  const std::map<long, Row> closed = run("error_feedback_on.csv", "1");
  const std::vector<long> selected = selections(closed);
  REQUIRE(!selected.empty());
  INFO("first selection at frame " << selected.front() << ", showing " << closed.at(selected.front()).configuration);
  // The first probe of a configuration other than the best: with no spread measured yet, its
  // corrected estimate is its measurement, and the log's est_error (of the frame's own
  // configuration) says so from the frame the governor learnt it. The governor measures a probe
  // before it decides the probe's frame, or, where the comparison comes later than the
  // frame's counters, before the next frame of its context; the next probe, 5 frames on, not
  // before its own frame.
  const auto first = std::find_if(closed.begin(), closed.end(), [&](const auto& r) {
    return r.second.probe_error >= 0.0 && r.second.configuration != best;
  });
  REQUIRE(first != closed.end());
  INFO("first probe of " << first->second.configuration << " at frame " << first->first << ": "
                         << first->second.probe_error);
  bool corrected = false;
  for (long k = first->first; k <= first->first + 8; ++k) {
    const auto it = closed.find(k);
    if (it != closed.end() && it->second.configuration == first->second.configuration)
      corrected = corrected || std::abs(it->second.est_error - first->second.probe_error) < 2e-6;
  }
  CHECK(corrected);
  // Probe frames showing a settled configuration (the same for the 10 frames before, no
  // transition) over the budget: each is met by a selection, which the log may show up to 10
  // frames before the probe frame's row for the same reason.
  int over = 0;
  for (const auto& [frame, row] : closed) {
    if (frame <= selected.front() + 10 || row.probe_error <= kBudget || row.configuration == best) continue;
    bool settled = true;
    for (long k = frame - 10; k < frame; ++k) {
      const auto it = closed.find(k);
      settled = settled && it != closed.end() && it->second.configuration == row.configuration &&
                it->second.decision != "transition";
    }
    if (!settled || closed.rbegin()->first < frame + 20) continue;
    ++over;
    INFO("frame " << frame << " at " << row.configuration << " measured " << row.probe_error);
    CHECK(
        std::any_of(selected.begin() + 1, selected.end(), [&](long s) { return s >= frame - 10 && s <= frame + 20; }));
  }
  if (over == 0) WARN("no settled probe measured the configuration shown over " << kBudget << ": reselection not seen");
}

TEST_CASE("a budget without a platform profile: one message, the app runs unchanged", "[integration]") {
  const std::string log = temp_path("no_profile.csv");
  unlink(log.c_str());
  const ProcessResult r = run_process(
      {DEMO_PATH, "--scene", "valley", "--detail", "0.05", "--width", "96", "--height", "54", "--frames", "3"},
      {{"LD_PRELOAD", shim_path()},
       {"GLBUDGET_POWER", "50%"},
       {"GLBUDGET_PROFILE", "/no/such/profile.json"},
       {"GLBUDGET_SENSOR", "cpu"},
       {"GLBUDGET_LOG", log}});
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(count_lines_with(r.err, "glbudget: no platform profile") == 1);
  const Frames f = frames_of(log);
  REQUIRE(f.configuration.size() == 3);
  for (auto& [frame, c] : f.configuration) CHECK(c == "0");
  for (auto& [frame, d] : f.decision) CHECK(d.empty());
  unlink(log.c_str());
}

TEST_CASE("a budget that does not parse: one message, the app observed only", "[integration]") {
  const ProcessResult r = run_process(
      {DEMO_PATH, "--scene", "valley", "--detail", "0.05", "--width", "96", "--height", "54", "--frames", "2"},
      {{"LD_PRELOAD", shim_path()},
       {"GLBUDGET_POWER", "lots"},
       {"GLBUDGET_PROFILE", kProfile},
       {"GLBUDGET_SENSOR", "cpu"}});
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(count_lines_with(r.err, "glbudget: power budget \"lots\"") == 1);
}

TEST_CASE("glmark2's terrain with no manifest under a 50 % budget: the window shrinks, the work falls",
          "[integration]") {
  // Resolution is the only knob. Paced at 10 fps, since power is saved only when frames leave
  // the processor idle; the same run without a budget is the baseline.
  auto run = [](const std::string& name, bool budget) {
    const std::string log = temp_path(name);
    unlink(log.c_str());
    std::map<std::string, std::string> env = {{"GLBUDGET_LOG", log},
                                              {"GLBUDGET_SENSOR", "cpu"},
                                              {"GLBUDGET_FPS", "10"},
                                              {"GLBUDGET_SELECT_FRAMES", "30"},
                                              {"GLBUDGET_TRANSITION_S", "1"}};
    if (budget) {
      env["GLBUDGET_POWER"] = "50%";
      env["GLBUDGET_PROFILE"] = kProfile;
    }
    const XvfbServer xvfb(700 + getpid() % 200 + (budget ? 1 : 0), "640x480x24");
    REQUIRE(xvfb.running());
    std::vector<std::string> argv = {"env", "DISPLAY=" + xvfb.display(), "LD_PRELOAD=" + preload_value(shim_path())};
    for (const auto& [k, v] : env) argv.push_back(k + "=" + v);
#ifdef SANITIZER_PRELOAD
    const char* scene = "terrain:duration=15";  // a sanitized shim draws at half the pace or less
#else
    const char* scene = "terrain:duration=9";
#endif
    for (const char* a : {"glmark2", "-s", "400x300", "-b", scene}) argv.push_back(a);
    const ProcessResult r = run_process(argv, {});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(r.out.find("glmark2 Score:") != std::string::npos);
    Frames f = frames_of(log);
    unlink(log.c_str());
    return f;
  };
#ifdef SANITIZER_PRELOAD
  // Under a sanitizer the shim's own work, not the window, sets the CPU time the power is
  // estimated from: what this build checks is that glmark2 ran clean to its end under the
  // governor, logged (glmark2 without a budget is interpose_integration's).
  CHECK(run("terrain_governed.csv", true).configuration.size() > 30);
  return;
#endif
  const Frames governed = run("terrain_governed.csv", true), free = run("terrain_free.csv", false);
  REQUIRE(governed.configuration.size() > 60);
  // From the first frame the governor shrank the window on, the work must stay well below the
  // free run's over the same frames. The last frame's configuration alone is not the test: when
  // the cpu estimate reads the budget as met, the governor may return to full scale for a while.
  long first_scaled = -1;
  size_t scaled_frames = 0;
  for (auto& [frame, c] : governed.configuration)
    if (c != "0") {
      if (first_scaled < 0) first_scaled = frame;
      ++scaled_frames;
    }
  REQUIRE(first_scaled >= 0);
  const long last = governed.fragments.rbegin()->first, last_free = free.fragments.rbegin()->first;
  const long until = std::min(last, last_free);
  const double work_governed = mean_of(governed.fragments, first_scaled, until);
  const double work_free = mean_of(free.fragments, first_scaled, until);
  INFO("frames " << first_scaled << ".." << until << ", " << scaled_frames << " of them scaled");
  CHECK(work_governed < 0.8 * work_free);
  CHECK(scaled_frames * 2 > static_cast<size_t>(until - first_scaled + 1));
  // The power, an estimate from CPU time, is reported, not asserted (see the demo's case).
  WARN("frames " << first_scaled << ".." << until << " (" << scaled_frames
                 << " scaled): " << mean_power(governed, first_scaled, until) << " W under the budget, "
                 << mean_power(free, first_scaled, until) << " W without; fragments " << work_governed << " against "
                 << work_free);
}
