// GLBUDGET_LOG: the per-frame CSV, written by a background thread so the render thread never
// does file I/O. Rows are flushed on exit, _exit and SIGTERM/SIGINT; a child forked without
// exec writes its own file (`run.csv` -> `run.<pid>.csv`). Rows are written whole (one
// write() per batch), so a killed process leaves no partial row; a write that fails (a full
// disk) is said once on stderr and ends the log, never the app.
#pragma once
#include <string>

#include "frame_row.hpp"

namespace glbudget {

constexpr const char* kFrameLogHeader =
    "frame,time_ns,context,pass,batches,vertices,fragments,primitives,gpu_ns,power_w,energy_j,sensor,sensor_dropped,"
    "configuration,predicted_w,budget_w,est_error,decision,probe,probe_error,probe_streams";

// Formats one row (no newline) into `out`; returns its length. Empty fields: not measured.
int format_row(const FrameRow& row, char* out, int size);

class FrameLog {
 public:
  static FrameLog& get();
  void set_path(const std::string& path);  // empty: logging off
  bool enabled() const { return !path_.empty(); }
  void push(const FrameRow& row);  // cheap; never touches the file
  void drain();                    // writes all queued rows now (exit paths)
  void drain_from_signal();        // the same, giving up rather than deadlocking
  void forked_child();             // called in a child after fork()

 private:
  FrameLog();
  static void* writer_main(void* self);
  void write_rows_locked();  // holds file_mu_
  bool open_file_locked();
  bool write_text_locked(const std::string& text);  // false (said once) when the file cannot take it

  std::string path_;
  struct Impl;
  Impl* impl_;
};

}  // namespace glbudget
