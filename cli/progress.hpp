#pragma once
// Progress on stderr: a bar with the time left, redrawn in place on a terminal; one plain line
// per update otherwise (a log, a pipe, a test).
#include <cstdio>
#include <string>

namespace glbudget::cli {

class Progress {
 public:
  explicit Progress(std::FILE* out);
  ~Progress() { clear(); }
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // done: share of the work done, in [0, 1]; seconds_left: an estimate; what: the current step.
  void update(double done, double seconds_left, const std::string& what);
  // A message that stays, printed above the bar.
  void message(const std::string& text);
  void clear();  // removes the bar (a terminal only)

 private:
  std::FILE* out_;
  bool terminal_;
  bool drawn_ = false;
};

}  // namespace glbudget::cli
