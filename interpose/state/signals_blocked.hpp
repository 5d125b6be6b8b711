// The shim's own threads (the log writer, the governor, the power sensor's sampler) are started
// inside a SignalsBlocked scope, so that they begin with every signal blocked: a process-directed
// signal then goes to one of the app's threads, as it would without the shim. With an empty
// mask, the app's SIGINT handler once ran on the log writer (ioquake3: SDL_Quit there while
// its main thread went on with the display being closed, then SIGSEGV).
#pragma once
#include <pthread.h>
#include <signal.h>

namespace glbudget {

class SignalsBlocked {
 public:
  SignalsBlocked() {
    sigset_t all;
    sigfillset(&all);
    pthread_sigmask(SIG_BLOCK, &all, &saved_);
  }
  ~SignalsBlocked() { pthread_sigmask(SIG_SETMASK, &saved_, nullptr); }
  SignalsBlocked(const SignalsBlocked&) = delete;
  SignalsBlocked& operator=(const SignalsBlocked&) = delete;

 private:
  sigset_t saved_{};
};

}  // namespace glbudget
