// The app's termination-signal handlers through the shim's sigaction() and signal(): linked
// into this test as into the shim, so this process's own calls reach them. A handler runs at
// once outside an AppSignalsDeferred scope, once at the scope's end inside one, and the app
// always sees its own actions.
#include "app_signals.hpp"

#include <dlfcn.h>
#include <signal.h>

#include <catch2/catch.hpp>

namespace glbudget {
// The shim's is in dispatch/hook_table.cpp; here nothing else defines dlsym.
void* real_dlsym(void* handle, const char* name) { return dlsym(handle, name); }
}  // namespace glbudget

namespace {
volatile sig_atomic_t g_int_runs = 0, g_term_runs = 0, g_usr_runs = 0, g_info_runs = 0;
volatile sig_atomic_t g_last_info_signal = 0;
void on_int(int) { g_int_runs = g_int_runs + 1; }
void on_term(int) { g_term_runs = g_term_runs + 1; }
void on_usr(int) { g_usr_runs = g_usr_runs + 1; }
void on_info(int sig, siginfo_t* info, void*) {
  g_info_runs = g_info_runs + 1;
  g_last_info_signal = info ? info->si_signo : -1;
  (void)sig;
}

void install(int sig, void (*handler)(int), int flags = 0) {
  struct sigaction sa {};
  sa.sa_handler = handler;
  sigemptyset(&sa.sa_mask);
  sigaddset(&sa.sa_mask, SIGUSR2);
  sa.sa_flags = flags;
  REQUIRE(sigaction(sig, &sa, nullptr) == 0);
}

void restore_default(int sig) {
  struct sigaction sa {};
  sa.sa_handler = SIG_DFL;
  sigemptyset(&sa.sa_mask);
  REQUIRE(sigaction(sig, &sa, nullptr) == 0);
}

void reset_counts() {
  g_int_runs = 0;
  g_term_runs = 0;
  g_usr_runs = 0;
  g_info_runs = 0;
  g_last_info_signal = 0;
}

// Catch2 has handlers of its own on some of these signals: each test puts them back.
class ActionsKept {
 public:
  ActionsKept() {
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], nullptr, &saved_[i]);
  }
  ~ActionsKept() {
    for (int i = 0; i < kCount; ++i) sigaction(kSignals[i], &saved_[i], nullptr);
  }

 private:
  static constexpr int kSignals[] = {SIGHUP, SIGINT, SIGQUIT, SIGTERM, SIGUSR1};
  static constexpr int kCount = 5;
  struct sigaction saved_[kCount] {};
};
}  // namespace

TEST_CASE("app signals: the app's handler runs at once outside the shim's GL work", "[unit][signals]") {
  const ActionsKept kept;
  reset_counts();
  install(SIGINT, on_int);
  raise(SIGINT);
  CHECK(g_int_runs == 1);
  restore_default(SIGINT);
}

TEST_CASE("app signals: inside the shim's GL work the handler waits for the scope's end", "[unit][signals]") {
  const ActionsKept kept;
  reset_counts();
  install(SIGINT, on_int);
  install(SIGTERM, on_term);
  {
    const AppSignalsDeferred outer;
    raise(SIGINT);
    raise(SIGINT);  // a standard signal taken twice while pending runs once, as the kernel's
    {
      const AppSignalsDeferred inner;
      raise(SIGTERM);
    }
    CHECK(g_int_runs == 0);  // the inner scope's end is not the outermost
    CHECK(g_term_runs == 0);
  }
  CHECK(g_int_runs == 1);
  CHECK(g_term_runs == 1);
  restore_default(SIGINT);
  restore_default(SIGTERM);
}

TEST_CASE("app signals: a hold defers them until it is released, after any open scope", "[unit][signals]") {
  const ActionsKept kept;
  reset_counts();
  install(SIGINT, on_int);
  hold_app_signals();
  raise(SIGINT);
  CHECK(g_int_runs == 0);  // a probe frame's app code between its GL calls
  {
    const AppSignalsDeferred deferred;
    release_app_signals();  // at the swap, inside the swap's own scope
    CHECK(g_int_runs == 0);
  }
  CHECK(g_int_runs == 1);
  hold_app_signals();
  raise(SIGINT);
  release_app_signals();
  CHECK(g_int_runs == 2);
}

TEST_CASE("app signals: sigaction reports the app's own action, never the trampoline", "[unit][signals]") {
  const ActionsKept kept;
  install(SIGHUP, on_int, SA_RESTART);
  struct sigaction now {};
  REQUIRE(sigaction(SIGHUP, nullptr, &now) == 0);
  CHECK(now.sa_handler == on_int);
  CHECK(!(now.sa_flags & SA_SIGINFO));
  CHECK((now.sa_flags & SA_RESTART));
  CHECK(sigismember(&now.sa_mask, SIGUSR2) == 1);
  // Replacing it returns the previous one as the app installed it.
  struct sigaction next {
  }, previous{};
  next.sa_sigaction = on_info;
  next.sa_flags = SA_SIGINFO;
  sigemptyset(&next.sa_mask);
  REQUIRE(sigaction(SIGHUP, &next, &previous) == 0);
  CHECK(previous.sa_handler == on_int);
  REQUIRE(sigaction(SIGHUP, nullptr, &now) == 0);
  CHECK(now.sa_sigaction == on_info);
  // Back to the default: the kernel's own action, and the previous report is the app's.
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  REQUIRE(sigaction(SIGHUP, &dfl, &previous) == 0);
  CHECK(previous.sa_sigaction == on_info);
  CHECK((previous.sa_flags & SA_SIGINFO));
  REQUIRE(sigaction(SIGHUP, nullptr, &now) == 0);
  CHECK(now.sa_handler == SIG_DFL);
}

TEST_CASE("app signals: SA_SIGINFO handlers get their siginfo, deferred or not", "[unit][signals]") {
  const ActionsKept kept;
  reset_counts();
  struct sigaction sa {};
  sa.sa_sigaction = on_info;
  sa.sa_flags = SA_SIGINFO;
  sigemptyset(&sa.sa_mask);
  REQUIRE(sigaction(SIGQUIT, &sa, nullptr) == 0);
  raise(SIGQUIT);
  CHECK(g_info_runs == 1);
  CHECK(g_last_info_signal == SIGQUIT);
  {
    const AppSignalsDeferred deferred;
    raise(SIGQUIT);
    CHECK(g_info_runs == 1);
  }
  CHECK(g_info_runs == 2);
  CHECK(g_last_info_signal == SIGQUIT);
  restore_default(SIGQUIT);
}

TEST_CASE("app signals: SA_RESETHAND runs the handler once, deferred too", "[unit][signals]") {
  const ActionsKept kept;
  reset_counts();
  install(SIGINT, on_int, SA_RESETHAND);
  {
    const AppSignalsDeferred deferred;
    raise(SIGINT);
  }
  CHECK(g_int_runs == 1);
  struct sigaction now {};
  REQUIRE(sigaction(SIGINT, nullptr, &now) == 0);
  CHECK(now.sa_handler == SIG_DFL);  // reset, as the kernel would have on delivery
}

TEST_CASE("app signals: signal() returns the app's previous handler and honours SIG_IGN", "[unit][signals]") {
  const ActionsKept kept;
  reset_counts();
  restore_default(SIGTERM);
  CHECK(signal(SIGTERM, on_term) == SIG_DFL);
  CHECK(signal(SIGTERM, on_int) == on_term);
  CHECK(signal(SIGTERM, SIG_IGN) == on_int);
  {
    const AppSignalsDeferred deferred;
    raise(SIGTERM);  // ignored by the kernel: nothing to run at the end either
  }
  CHECK(g_int_runs == 0);
  CHECK(g_term_runs == 0);
  CHECK(signal(SIGTERM, SIG_DFL) == SIG_IGN);
}

TEST_CASE("app signals: other signals are not deferred", "[unit][signals]") {
  const ActionsKept kept;
  reset_counts();
  CHECK(signal(SIGUSR1, on_usr) == SIG_DFL);
  {
    const AppSignalsDeferred deferred;
    raise(SIGUSR1);
    CHECK(g_usr_runs == 1);
  }
  struct sigaction now {};
  REQUIRE(sigaction(SIGUSR1, nullptr, &now) == 0);
  CHECK(now.sa_handler == on_usr);
  signal(SIGUSR1, SIG_DFL);
}
