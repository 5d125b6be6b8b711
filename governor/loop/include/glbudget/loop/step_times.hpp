#pragma once
// How long the governor's steps take, as running statistics for the shim's log and the
// bench: last, mean and max in microseconds.
#include <cstddef>
#include <string>

namespace glbudget::loop {

struct RunningStats {
  std::size_t count = 0;
  double last_us = 0.0;
  double mean_us = 0.0;
  double max_us = 0.0;

  void add(double us);
};

struct StepTimes {
  RunningStats predict_frame;    // the frame's own power (every frame the model sees)
  RunningStats learn;            // learning from a frame with power, fits included
  RunningStats fit;              // those learn calls that fitted (window, reuse, history)
  RunningStats predict_all;      // power of every configuration, at a selection
  RunningStats estimate_errors;  // error of every configuration, at a selection
  RunningStats select;           // the search, at a selection
};

// "fit 85.1/80.2/310.0 us (3), learn ..., select ...": last/mean/max and count of each step.
std::string describe(const StepTimes& times);

}  // namespace glbudget::loop
