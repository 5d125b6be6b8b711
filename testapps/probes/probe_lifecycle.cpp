// Process life cycle around the shim:
//   --exit normal|_exit|sigterm   how the process ends after its frames
//   --fork                        after the frames, fork twice: one child makes a context of
//                                 its own and renders (its own log), one never uses GL and
//                                 leaves with _exit (no log); prints "child <pid>" for each
//   --fork-interrupted            after the frames, fork a child that draws nothing and is
//                                 stopped by SIGINT, as Ctrl-C stops a whole process group;
//                                 prints "child interrupted after <ms> ms" (5: it was not)
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

static int render(const ProbeArgs& args, int frames) {
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_lifecycle", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  GlFns gl;
  gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); });
  KnownScene scene(gl, ShaderDialect::kGlsl330Core, args.width, args.height);
  if (!scene.ok()) return 2;
  for (int f = 0; f < frames; ++f) {
    scene.draw_frame(f);
    egl.SwapBuffers(w.display, w.surface);
  }
  return write_ppm(args.out, scene.read_rgba(), args.width, args.height) ? 0 : 3;
}

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  const char* exit_mode = "normal";
  bool do_fork = false, fork_interrupted = false;
  for (int i = 1; i < argc; ++i) {
    if (!strcmp(argv[i], "--exit") && i + 1 < argc) exit_mode = argv[i + 1];
    if (!strcmp(argv[i], "--fork")) do_fork = true;
    if (!strcmp(argv[i], "--fork-interrupted")) fork_interrupted = true;
  }
  if (do_fork) {
    // Children first, before the parent has a context: a forked GL context is not usable.
    pid_t renderer = fork();
    if (renderer == 0) {
      ProbeArgs child = args;
      child.out.clear();
      exit(render(child, 3));
    }
    pid_t idle = fork();
    if (idle == 0) _exit(0);
    printf("child %d\nchild %d\n", (int)renderer, (int)idle);
    fflush(stdout);
    int status = 0;
    waitpid(renderer, &status, 0);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) return 4;
    waitpid(idle, &status, 0);
  }
  int rc = render(args, args.frames);
  if (fork_interrupted) {
    const auto start = std::chrono::steady_clock::now();
    const pid_t child = fork();
    if (child == 0) {
      raise(SIGINT);
      _exit(0);
    }
    int status = 0;
    waitpid(child, &status, 0);
    const auto ms =
        std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - start).count();
    if (!WIFSIGNALED(status) || WTERMSIG(status) != SIGINT) return 5;
    printf("child interrupted after %lld ms\n", static_cast<long long>(ms));
  }
  if (!strcmp(exit_mode, "_exit")) _exit(rc);
  if (!strcmp(exit_mode, "sigterm")) raise(SIGTERM);
  return rc;
}
