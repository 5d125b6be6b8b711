// The app's handlers of the termination signals (SIGINT, SIGTERM, SIGHUP, SIGQUIT) never run
// in the middle of the shim's own GL work on the thread they interrupt.
//
// Games quit from such handlers, and some tear down GL there: ioquake3's SIGINT handler runs
// SDL_Quit, which destroys the context. Interrupting a GL call that waits inside the driver,
// that destroys what the call waits on: llvmpipe's glXMakeCurrent waited forever to destroy the
// condition variable its interrupted draw was waiting on. Without the shim the app takes that
// risk in its own calls (OpenArena: 1 quit in 8 hung in its swap); the shim's probe frames,
// whose every draw is drawn again and waits longer, must not add to it.
//
// So the shim interposes sigaction() and signal() for those four signals: the kernel runs a
// trampoline of ours, which calls the app's handler at once, except on a thread inside an
// AppSignalsDeferred scope or a hold, where it only notes the signal; the scope's (or hold's)
// end raises it again on that thread, and the app's handler runs there. The signal
// masks are left alone, so the kernel picks the same thread it would without the shim. The app
// sees its own handlers through sigaction(), never ours.
#pragma once

namespace glbudget {

namespace app_signals_detail {
extern thread_local int t_depth __attribute__((tls_model("initial-exec")));
extern thread_local volatile int t_held __attribute__((tls_model("initial-exec")));
void run_deferred();
}  // namespace app_signals_detail

// A probe frame defers them from its first GL call to the shim's work at its swap, the app's
// own calls included: they wait in the driver behind the probe's work (ioquake3's interrupted
// glClear did). The app's real swap is not held: it may block for long.
inline void hold_app_signals() { app_signals_detail::t_held = 1; }
// Ends the hold; what was deferred runs now, or at the end of the open scope.
void release_app_signals();

class AppSignalsDeferred {
 public:
  AppSignalsDeferred() { ++app_signals_detail::t_depth; }
  ~AppSignalsDeferred() {
    if (--app_signals_detail::t_depth == 0) app_signals_detail::run_deferred();
  }
  AppSignalsDeferred(const AppSignalsDeferred&) = delete;
  AppSignalsDeferred& operator=(const AppSignalsDeferred&) = delete;
};

}  // namespace glbudget
