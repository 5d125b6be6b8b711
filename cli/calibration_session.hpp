#pragma once
// The measurements of `glbudget calibrate`: the idle step, then the batches, vertices and
// fragments sweeps (analysis/calibration.hpp says why and how they are judged), each run as one
// calibrate_load process paced at a fixed frame rate, within a time budget.
#include <string>
#include <vector>

#include "glbudget/analysis/calibration.hpp"
#include "load_runner.hpp"
#include "progress.hpp"

namespace glbudget::cli {

struct SessionSettings {
  double fps = 30.0;       // the paper's frame rate; saturation counts are per frame at this rate
  double idle_s = 1.0;     // the idle step
  double step_s = 0.4;     // each sweep step
  double factor = 2.0;     // count ratio from one step to the next
  double budget_s = 52.0;  // for everything, startups included
  int max_steps = 24;      // per sweep
};

// A step as measured, for the report.
struct MeasuredStep {
  double count = 0.0;  // the swept quantity per frame, as logged (as asked for where not logged)
  double power_w = 0.0;
  long long frames = 0;
  bool late = false;
};

struct SweepRecord {
  const char* name = "";
  std::vector<MeasuredStep> steps;
  analysis::SweepMeasurement measurement;
};

class CalibrationSession {
 public:
  CalibrationSession(LoadRunner& runner, Progress& progress, const SessionSettings& settings);

  // Runs every step, or up to an interrupt. False (with `error`) when the load failed or the
  // sensor gave nothing.
  bool run(std::string& error);

  analysis::CalibrationMeasurements measurements() const;
  const std::vector<SweepRecord>& sweeps() const { return sweeps_; }
  double seconds() const;

 private:
  struct Quantity;
  bool run_idle(std::string& error);
  bool run_sweep(const Quantity& q, std::string& error);
  double seconds_left_estimate(int sweep, int steps_done) const;

  LoadRunner& runner_;
  Progress& progress_;
  SessionSettings settings_;
  double start_s_ = 0.0;
  double idle_w_;
  std::vector<SweepRecord> sweeps_;
  // Measured as the session goes, for the time-left estimate.
  double startup_s_ = 0.5;
  double step_wall_s_;
  int expected_steps_;
};

}  // namespace glbudget::cli
