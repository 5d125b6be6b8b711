#pragma once
// Runs testapps/calibrate_load under the shim with a frame log, and collects what each of its
// steps presented. SIGINT (Ctrl-C) ends the load after its current frame; what it drew so far
// is still collected.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "glbudget/analysis/frame_log.hpp"

namespace glbudget::cli {

// One line of the load's stdout: a step it drew (see calibrate_load --help).
struct LoadStep {
  double batches = 0.0, vertices = 0.0, fragments = 0.0;  // as asked for
  std::int64_t start_ns = 0, end_ns = 0, frames = 0;
  bool late = false;         // ran at under half the paced rate
  bool interrupted = false;  // cut short
};

struct LoadRun {
  std::vector<LoadStep> steps;
  std::vector<analysis::LoggedFrame> frames;  // the log's, in order
  bool failed = false;
  std::string failure;  // what went wrong, for a `glbudget:` line
};

class LoadRunner {
 public:
  // sensor: a GLBUDGET_SENSOR value; work_dir: where the logs go (the caller removes it).
  LoadRunner(std::string load, std::string shim, std::string sensor, std::string work_dir);

  // Runs `load args...`; on_step sees each step as it ends.
  LoadRun run(const std::vector<std::string>& args, const std::function<void(const LoadStep&)>& on_step);

 private:
  std::vector<std::string> environment(const std::string& log) const;

  std::string load_, shim_, sensor_, work_dir_;
  int runs_ = 0;
};

// SIGINT and SIGTERM set a flag (and reach the running load) instead of ending glbudget.
void catch_interrupts();
bool interrupted();

}  // namespace glbudget::cli
