#include "calibration_session.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace glbudget::cli {

namespace {

double now_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

std::string number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.0f", value);
  return text;
}

constexpr int kWidth = 256, kHeight = 256;  // one full-screen layer: 65536 fragments

}  // namespace

// What one sweep varies, from where, and how far at most. The others stay small: one batch of
// one triangle (clipped, so no fragment), no fragments.
struct CalibrationSession::Quantity {
  const char* name;
  double first;
  double cap;
};

CalibrationSession::CalibrationSession(LoadRunner& runner, Progress& progress, const SessionSettings& settings)
    : runner_(runner),
      progress_(progress),
      settings_(settings),
      idle_w_(std::numeric_limits<double>::quiet_NaN()),
      step_wall_s_(settings.step_s * 1.1),
      expected_steps_(settings.factor >= 4.0 ? 8 : 15) {}

double CalibrationSession::seconds() const { return now_s() - start_s_; }

analysis::CalibrationMeasurements CalibrationSession::measurements() const {
  analysis::CalibrationMeasurements m;
  m.idle_w = idle_w_;
  analysis::SweepMeasurement* targets[3] = {&m.batches, &m.vertices, &m.fragments};
  for (std::size_t i = 0; i < sweeps_.size() && i < 3; ++i) *targets[i] = sweeps_[i].measurement;
  return m;
}

double CalibrationSession::seconds_left_estimate(int sweep, int steps_done) const {
  double left = 0.0;
  if (sweep < 0) left += settings_.idle_s + startup_s_;
  for (int s = std::max(sweep, 0); s < 3; ++s) {
    const int steps = s == sweep ? std::max(expected_steps_ - steps_done, 2) : expected_steps_;
    left += steps * step_wall_s_ + (s == sweep ? 0.0 : startup_s_);
  }
  return left;
}

bool CalibrationSession::run(std::string& error) {
  start_s_ = now_s();
  if (!run_idle(error)) return false;
  static const Quantity quantities[3] = {
      {"batches", 16, 4194304.0}, {"vertices", 1024, 1073741824.0}, {"fragments", 65536, 68719476736.0}};
  for (const Quantity& q : quantities) {
    if (interrupted()) break;
    if (!run_sweep(q, error)) return false;
  }
  progress_.clear();
  return true;
}

bool CalibrationSession::run_idle(std::string& error) {
  progress_.update(0.0, seconds_left_estimate(-1, 0), "idle power");
  const double started = now_s();
  const LoadRun run = runner_.run(
      {"--batches", "1", "--vertices", "3", "--fps", number(settings_.fps), "--seconds",
       std::to_string(settings_.idle_s), "--width", std::to_string(kWidth), "--height", std::to_string(kHeight)},
      nullptr);
  if (run.failed) {
    error = run.failure;
    return false;
  }
  if (run.steps.empty()) return true;  // interrupted before it began
  const LoadStep& step = run.steps.front();
  idle_w_ =
      analysis::measure_step(run.frames, static_cast<double>(step.start_ns), static_cast<double>(step.end_ns)).power_w;
  startup_s_ = std::max(0.0, now_s() - started - static_cast<double>(step.end_ns - step.start_ns) * 1e-9);
  if (!std::isfinite(idle_w_) && !interrupted()) {
    error = "the sensor gave no power readings for the idle frames";
    return false;
  }
  return true;
}

// One calibrate_load process per sweep: it stops on its own two steps after its frames fall
// under half the paced rate (past the knee, see analysis/calibration.hpp), or at `steps`.
bool CalibrationSession::run_sweep(const Quantity& q, std::string& error) {
  SweepRecord& record = sweeps_.emplace_back();
  record.name = q.name;
  const int sweep_index = static_cast<int>(sweeps_.size()) - 1;
  const double share_s = (settings_.budget_s - seconds()) / (3 - sweep_index) - startup_s_;
  const int to_cap = 1 + static_cast<int>(std::floor(std::log(q.cap / q.first) / std::log(settings_.factor)));
  const int steps = std::clamp(static_cast<int>(share_s / step_wall_s_), 3, std::min(settings_.max_steps, to_cap));
  const std::string name = q.name;
  auto count_of = [&](const std::string& which) -> std::string {
    return which == name ? number(q.first) : which == "batches" ? "1" : which == "vertices" ? "3" : "0";
  };
  const std::vector<std::string> args = {"--sweep",
                                         name,
                                         "--batches",
                                         count_of("batches"),
                                         "--vertices",
                                         count_of("vertices"),
                                         "--fragments",
                                         count_of("fragments"),
                                         "--fps",
                                         number(settings_.fps),
                                         "--seconds",
                                         std::to_string(settings_.step_s),
                                         "--factor",
                                         std::to_string(settings_.factor),
                                         "--steps",
                                         std::to_string(steps),
                                         "--stop-when-late",
                                         "2",
                                         "--width",
                                         std::to_string(kWidth),
                                         "--height",
                                         std::to_string(kHeight)};
  auto swept = [&](const LoadStep& step) {
    return name == "batches" ? step.batches : name == "vertices" ? step.vertices : step.fragments;
  };
  int seen = 0;
  const double started = now_s();
  double step_time = 0.0;
  const LoadRun run = runner_.run(args, [&](const LoadStep& step) {
    ++seen;
    step_time += static_cast<double>(step.end_ns - step.start_ns) * 1e-9;
    char what[96];
    std::snprintf(what, sizeof what, "%s sweep: %.0f per frame%s", q.name, swept(step), step.late ? " (late)" : "");
    const double left = seconds_left_estimate(sweep_index, seen);
    progress_.update(seconds() / (seconds() + left), left, what);
  });
  if (run.failed) {
    error = run.failure;
    return false;
  }
  if (seen > 0) {
    step_wall_s_ = 0.5 * step_wall_s_ + 0.5 * step_time / seen;
    startup_s_ = std::max(0.0, now_s() - started - step_time);
  }
  for (const LoadStep& step : run.steps) {
    const analysis::StepMeasurement m =
        analysis::measure_step(run.frames, static_cast<double>(step.start_ns), static_cast<double>(step.end_ns));
    // The counts the shim logged are the ones the model will see; what was asked for stands in
    // where the driver reported none.
    const double asked = name == "vertices" ? step.batches * std::ceil(step.vertices / 3.0) * 3.0 : swept(step);
    const double logged = name == "batches" ? m.batches : name == "vertices" ? m.vertices : m.fragments;
    const double count = std::isfinite(logged) && logged > 0.0 ? logged : asked;
    record.steps.push_back({count, m.power_w, step.frames, step.late});
    record.measurement.points.push_back({count, m.power_w, step.late});
  }
  record.measurement.complete = !interrupted();
  int total_steps = 0;
  for (const SweepRecord& s : sweeps_) total_steps += static_cast<int>(s.steps.size());
  expected_steps_ = std::max(4, total_steps / (sweep_index + 1));
  return true;
}

}  // namespace glbudget::cli
