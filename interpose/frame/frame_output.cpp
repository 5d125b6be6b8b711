#include "frame_output.hpp"

#include <pthread.h>
#include <signal.h>
#include <unistd.h>
#include <time.h>

#include <atomic>
#include <cerrno>
#include <cmath>
#include <mutex>

#include "app_signals.hpp"
#include "configuration.hpp"
#include "governing.hpp"
#include "context_state.hpp"
#include "frame_log.hpp"
#include "options.hpp"
#include "probes.hpp"
#include "render_targets.hpp"
#include "shader_instrumentation.hpp"
#include "signals_blocked.hpp"
#include "window_size.hpp"
#include "glbudget/sensors/sensor.hpp"

namespace glbudget {

namespace {
// When governing, rows reach the log through the governor thread, which annotates them.
// The context whose rows are being emitted, for their probe flag.
thread_local const ContextState* t_emitting = nullptr;

void emit_row(const FrameRow& in) {
  FrameRow row = in;
  row.probe = t_emitting && t_emitting->probes && t_emitting->probes->was_probe_frame(row.frame);
  if (row.probe) row.probe_sweep_streams = t_emitting->probes->sweep_streams_of(row.frame);
  if (governing())
    governor_push(row);
  else
    FrameLog::get().push(row);
}

// Set while this thread runs the code that changes a counter's queue of pending frames.
thread_local bool t_in_frame_code = false;
struct InFrameCode {
  InFrameCode() { t_in_frame_code = true; }
  ~InFrameCode() { t_in_frame_code = false; }
};

void on_fatal_signal(int sig) {
  int saved = errno;
  // Frames still awaiting GPU results are logged with CPU figures, if the signal did not
  // interrupt this thread in the middle of changing them (no GL call is made here).
  ContextState* c = current_context();
  if (c && !t_in_frame_code) flush_pending_frames(*c, FlushMode::kCpuOnly);
  governor_drain_from_signal();
  FrameLog::get().drain_from_signal();
  signal(sig, SIG_DFL);
  errno = saved;
  raise(sig);
}

// Only where the app has not taken the signal itself: an app's handler usually ends in
// exit(), which reaches our atexit flush.
void install_signal_flush(int sig) {
  struct sigaction old {};
  if (sigaction(sig, nullptr, &old) != 0 || old.sa_handler != SIG_DFL || (old.sa_flags & SA_SIGINFO)) return;
  struct sigaction sa {};
  sa.sa_handler = on_fatal_signal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;
  sigaction(sig, &sa, nullptr);
}

void pace(ContextState& c, double fps) {
  const int64_t period = static_cast<int64_t>(std::llround(1e9 / fps));
  const int64_t now = sensors::monotonic_now_ns();
  if (c.next_deadline_ns == 0 || now > c.next_deadline_ns + period) {
    c.next_deadline_ns = now + period;  // first frame, or fell behind: restart the cadence
    return;
  }
  if (now < c.next_deadline_ns) {
    timespec ts{static_cast<time_t>(c.next_deadline_ns / 1000000000),
                static_cast<long>(c.next_deadline_ns % 1000000000)};
    while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
    }
  }
  c.next_deadline_ns += period;
}
}  // namespace

void flush_pending_frames(ContextState& c, FlushMode mode) {
  if (!c.counter) return;
  InFrameCode guard;
  t_emitting = &c;
  switch (mode) {
    case FlushMode::kCollect:
      if (c.probes) c.probes->collect(false);
      c.counter->collect(emit_row, PassCounter::Collect::kAvailable);
      break;
    case FlushMode::kWait:
      if (c.probes) c.probes->collect(true);
      c.counter->collect(emit_row, PassCounter::Collect::kWait);
      break;
    case FlushMode::kCpuOnly:
      c.counter->collect(emit_row, PassCounter::Collect::kCpuOnly);
      break;
  }
  t_emitting = nullptr;
  governor_rows_done();
}

namespace {
// The power sensor (GLBUDGET_SENSOR), opened when frames are logged. Never destroyed: its
// sampling thread may outlive every static destructor, and the OS reclaims it at exit.
sensors::PowerSensor* g_sensor = nullptr;
std::mutex g_sensor_mu;  // on_swap() is single-threaded; contexts may swap on several threads

sensors::FrameEnergy frame_energy(int64_t now_ns) {
  if (!g_sensor) return {};
  std::lock_guard lock(g_sensor_mu);
  return g_sensor->on_swap(now_ns);
}

std::atomic<bool> g_started{false};
std::atomic<pid_t> g_pid{0};  // the process that logs; vfork/posix_spawn children differ

void forked_child() {
  g_pid = getpid();
  // Frames still awaiting results belong to the parent, which logs them.
  for_each_context([](ContextState& c) {
    if (c.counter) c.counter->discard_pending();
  });
}
}  // namespace

void frame_output_started() {
  static std::once_flag once;
  std::call_once(once, [] {
    g_pid = getpid();
    pthread_atfork(nullptr, nullptr, forked_child);
    g_started = true;
    const Options& o = options();
    FrameLog::get().set_path(o.log_path);
    atexit(final_flush);
    const bool governed = governor_start();
    if (FrameLog::get().enabled() || governed) {
      install_signal_flush(SIGTERM);
      install_signal_flush(SIGINT);
      const SignalsBlocked blocked;  // its sampling thread takes none of the app's signals
      g_sensor = sensors::open_sensor_from_environment().release();
    }
  });
}

void swap_begin() {
  ContextState* c = current_context();
  if (!c) return;
  // Pacing sleeps before the frame is presented, so frames reach the screen evenly spaced.
  if (options().fps > 0) pace(*c, options().fps);
  const AppSignalsDeferred deferred;
  InFrameCode guard;
  const int64_t now = sensors::monotonic_now_ns();
  c->counter->end_frame(++c->frame, now, c->index, frame_energy(now));
  if (c->probes) c->probes->before_present();
  if (c->targets) {
    c->targets->present();  // the scaled window into the real back buffer
    c->targets->end_frame();
  }
  if (c->probes) c->probes->after_present();
  // A probe frame's hold ends before the app's own swap, which may block for long (a hidden
  // window's vsync): the app's handler must be able to interrupt it, as without the shim.
  release_app_signals();
}

void swap_end() {
  ContextState* c = current_context();
  if (!c) return;
  const AppSignalsDeferred deferred;
  flush_pending_frames(*c, FlushMode::kCollect);
  instrumentation_swap(*c);
  if (c->targets) {
    int w = 0, h = 0;
    if (current_window_size(c->egl, &w, &h)) c->targets->set_window_size(w, h);
  }
  // A new configuration starts with a frame, never in the middle of one.
  apply_configuration(*c, configuration_for_frame(c->frame + 1));
  if (c->probes) c->probes->after_swap(c->frame + 1);
}

void final_flush() {
  // Inert in processes that never drew, and in children sharing the parent's memory
  // (vfork, posix_spawn) on their way to exec or _exit.
  if (!g_started || g_pid != getpid()) return;
  static std::atomic<bool> done{false};
  if (done.exchange(true)) return;
  ContextState* here = current_context();
  // The context current on the exiting thread can still answer its queries (waiting is
  // harmless now); others cannot be asked from here, so they log CPU figures.
  if (here) flush_pending_frames(*here, FlushMode::kWait);
  if (here) instrumentation_release(*here);
  for_each_context([](ContextState& c) {
    if (&c != current_context() && !c.bound) flush_pending_frames(c, FlushMode::kCpuOnly);
  });
  governor_stop();  // its queued frames are decided and logged first
  FrameLog::get().drain();
  report_unmatched_passes();
}

}  // namespace glbudget
