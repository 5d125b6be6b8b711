// sigaction() and signal() for the termination signals, and the trampoline that defers the
// app's handlers out of the shim's GL work (app_signals.hpp).
#include "app_signals.hpp"

#include <dlfcn.h>
#include <errno.h>
#include <pthread.h>
#include <signal.h>

#include <atomic>

// Exported through the shim's version script (dispatch/gen/gen_hooks.py).
#define GLBUDGET_SIGNAL_EXPORT extern "C" __attribute__((visibility("default")))

namespace glbudget {

// glibc's dlsym past the shim's own (dispatch/hook_table.cpp).
void* real_dlsym(void* handle, const char* name);

namespace app_signals_detail {
thread_local int t_depth __attribute__((tls_model("initial-exec"))) = 0;
thread_local volatile int t_held __attribute__((tls_model("initial-exec"))) = 0;
}  // namespace app_signals_detail

namespace {
using app_signals_detail::t_depth;
using app_signals_detail::t_held;

constexpr int kDeferred[] = {SIGHUP, SIGINT, SIGQUIT, SIGTERM};
bool deferrable(int sig) {
  for (int s : kDeferred)
    if (s == sig) return true;
  return false;
}

// Signals taken inside a scope on this thread, one bit each (all four are below 32).
thread_local volatile sig_atomic_t t_pending __attribute__((tls_model("initial-exec"))) = 0;

// The app's action for each deferrable signal whose handler is a function (the kernel runs
// the trampoline instead); the handler is null where the app's action is the kernel's own.
struct AppAction {
  std::atomic<void*> handler{nullptr};
  std::atomic<int> flags{0};
  sigset_t mask{};
};
AppAction g_actions[32];

// The next definition after ours (glibc's, or a sanitizer's interceptor), looked up without a
// function-local static's guard, which ThreadSanitizer intercepts; racing threads store the
// same value.
void* next_definition(std::atomic<void*>& cache, const char* name) {
  void* p = cache.load(std::memory_order_acquire);
  if (!p) {
    p = real_dlsym(RTLD_NEXT, name);
    cache.store(p, std::memory_order_release);
  }
  return p;
}

using SigactionFn = int (*)(int, const struct sigaction*, struct sigaction*);
std::atomic<void*> g_next_sigaction{nullptr};
SigactionFn real_sigaction() { return reinterpret_cast<SigactionFn>(next_definition(g_next_sigaction, "sigaction")); }
using SignalFn = sighandler_t (*)(int, sighandler_t);
std::atomic<void*> g_next_signal{nullptr};
SignalFn real_signal() { return reinterpret_cast<SignalFn>(next_definition(g_next_signal, "signal")); }

void run_app_handler(int sig, siginfo_t* info, void* context) {
  AppAction& a = g_actions[sig];
  void* handler = a.handler.load(std::memory_order_acquire);
  const int flags = a.flags.load(std::memory_order_relaxed);
  if (!handler) return;  // the app put its action back to the kernel's while this was on its way
  if (flags & SA_RESETHAND) {
    // The kernel would have reset it on delivery; the trampoline is installed without the flag
    // so that a deferred signal still finds the app's handler.
    a.handler.store(nullptr, std::memory_order_release);
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    real_sigaction()(sig, &dfl, nullptr);
  }
  if (flags & SA_SIGINFO)
    reinterpret_cast<void (*)(int, siginfo_t*, void*)>(handler)(sig, info, context);
  else
    reinterpret_cast<void (*)(int)>(handler)(sig);
}

void trampoline(int sig, siginfo_t* info, void* context) {
  if (t_depth > 0 || t_held) {
    t_pending = t_pending | (1 << sig);
    return;
  }
  run_app_handler(sig, info, context);
}

bool is_trampoline(const struct sigaction& sa) { return (sa.sa_flags & SA_SIGINFO) && sa.sa_sigaction == trampoline; }

bool is_function(const struct sigaction* act) {
  if (act->sa_flags & SA_SIGINFO) return act->sa_sigaction != nullptr;
  return act->sa_handler != SIG_DFL && act->sa_handler != SIG_IGN && act->sa_handler != SIG_ERR;
}

// An AppAction's contents at one moment.
struct AppRecord {
  void* handler = nullptr;
  int flags = 0;
  sigset_t mask{};
};
AppRecord record_of(int sig) {
  const AppAction& a = g_actions[sig];
  return {a.handler.load(std::memory_order_acquire), a.flags.load(std::memory_order_relaxed), a.mask};
}

// What the app installed, as sigaction() reports it: the kernel's action, unless that is the
// trampoline standing for `app`.
void app_view(const struct sigaction& kernel, const AppRecord& app, struct sigaction* out) {
  *out = kernel;
  if (!is_trampoline(kernel) || !app.handler) return;
  if (app.flags & SA_SIGINFO)
    out->sa_sigaction = reinterpret_cast<void (*)(int, siginfo_t*, void*)>(app.handler);
  else
    out->sa_handler = reinterpret_cast<void (*)(int)>(app.handler);
  out->sa_flags = app.flags;
  out->sa_mask = app.mask;
}

int app_sigaction(int sig, const struct sigaction* act, struct sigaction* old) {
  SigactionFn real = real_sigaction();
  if (!real) {
    errno = ENOSYS;
    return -1;
  }
  if (!deferrable(sig)) return real(sig, act, old);
  // Taken before the change, for the previous action where the kernel held the trampoline.
  const AppRecord before = record_of(sig);
  struct sigaction kernel_old {};
  int rc;
  if (!act) {
    rc = real(sig, nullptr, &kernel_old);
  } else if (is_function(act)) {
    // Recorded before the kernel may deliver through the trampoline.
    AppAction& a = g_actions[sig];
    a.mask = act->sa_mask;
    a.flags.store(act->sa_flags, std::memory_order_relaxed);
    a.handler.store((act->sa_flags & SA_SIGINFO) ? reinterpret_cast<void*>(act->sa_sigaction)
                                                 : reinterpret_cast<void*>(act->sa_handler),
                    std::memory_order_release);
    struct sigaction mine = *act;
    mine.sa_sigaction = trampoline;
    mine.sa_flags = (act->sa_flags | SA_SIGINFO) & ~SA_RESETHAND;
    rc = real(sig, &mine, &kernel_old);
  } else {
    rc = real(sig, act, &kernel_old);
    if (rc == 0) g_actions[sig].handler.store(nullptr, std::memory_order_release);
  }
  if (rc == 0 && old) app_view(kernel_old, before, old);
  return rc;
}

// signal()'s BSD semantics, as glibc gives them: the signal blocked in its handler, and
// system calls restarted.
sighandler_t app_signal(int sig, sighandler_t handler) {
  struct sigaction act {
  }, old{};
  act.sa_handler = handler;
  sigemptyset(&act.sa_mask);
  sigaddset(&act.sa_mask, sig);
  act.sa_flags = SA_RESTART;
  if (app_sigaction(sig, &act, &old) != 0) return SIG_ERR;
  if (old.sa_flags & SA_SIGINFO) return reinterpret_cast<sighandler_t>(reinterpret_cast<void*>(old.sa_sigaction));
  return old.sa_handler;
}
}  // namespace

void release_app_signals() {
  t_held = 0;
  if (t_depth == 0) app_signals_detail::run_deferred();
}

void app_signals_detail::run_deferred() {
  if (!t_pending || t_held) return;
  const int saved = errno;
  for (int sig : kDeferred) {
    if (!(t_pending & (1 << sig))) continue;
    t_pending = t_pending & ~(1 << sig);
    // Raised on this thread with no scope open: the trampoline calls the app's handler.
    pthread_kill(pthread_self(), sig);
  }
  errno = saved;
}

}  // namespace glbudget

using namespace glbudget;

GLBUDGET_SIGNAL_EXPORT int sigaction(int sig, const struct sigaction* __restrict act,
                                     struct sigaction* __restrict old) noexcept {
  return app_sigaction(sig, act, old);
}

GLBUDGET_SIGNAL_EXPORT sighandler_t signal(int sig, sighandler_t handler) noexcept {
  if (!deferrable(sig)) {
    SignalFn real = real_signal();
    if (!real) return SIG_ERR;
    return real(sig, handler);
  }
  return app_signal(sig, handler);
}

GLBUDGET_SIGNAL_EXPORT sighandler_t bsd_signal(int sig, sighandler_t handler) noexcept { return signal(sig, handler); }
