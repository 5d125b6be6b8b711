// An app with a signal handler, as games have for SIGINT: every frame it sends itself a
// process-directed SIGUSR1 while its own thread blocks it, waits a moment, then unblocks it.
// A thread that does not block the signal takes it in the meantime. The app's threads (and
// llvmpipe's) block every signal, so without the shim the handler always runs on the main
// thread; a thread of the shim's with an empty mask would take it. Exits 6 if the handler ran
// on another thread (or never ran), after writing the last image as the other probes do.
#include <pthread.h>
#include <signal.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <ctime>

#include "common/egl_setup.hpp"
#include "common/probe_main.hpp"

namespace {
std::atomic<int> on_main{0}, elsewhere{0};
pid_t main_tid = 0;
void taken(int) {
  if (static_cast<pid_t>(syscall(SYS_gettid)) == main_tid)
    on_main.fetch_add(1);
  else
    elsewhere.fetch_add(1);
}
}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  main_tid = static_cast<pid_t>(syscall(SYS_gettid));
  struct sigaction sa {};
  sa.sa_handler = taken;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGUSR1, &sa, nullptr);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_signals", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  GlFns gl;
  gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); });
  sigset_t usr1;
  sigemptyset(&usr1);
  sigaddset(&usr1, SIGUSR1);
  const int rc = run_known_scene(gl, ShaderDialect::kGlsl330Core, args, [&] {
    egl.SwapBuffers(w.display, w.surface);
    pthread_sigmask(SIG_BLOCK, &usr1, nullptr);
    kill(getpid(), SIGUSR1);
    const timespec moment{0, 5'000'000};
    nanosleep(&moment, nullptr);
    pthread_sigmask(SIG_UNBLOCK, &usr1, nullptr);
  });
  fprintf(stderr, "probe_signals: SIGUSR1 taken %d times on the main thread, %d on others\n", on_main.load(),
          elsewhere.load());
  if (rc != 0) return rc;
  return elsewhere.load() == 0 && on_main.load() == args.frames ? 0 : 6;
}
