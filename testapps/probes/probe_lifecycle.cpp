// Process life cycle around the shim:
//   --exit normal|_exit|sigterm   how the process ends after its frames
//   --fork                        after the frames, fork twice: one child makes a context of
//                                 its own and renders (its own log), one never uses GL and
//                                 leaves with _exit (no log); prints "child <pid>" for each
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

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
  bool do_fork = false;
  for (int i = 1; i < argc; ++i) {
    if (!strcmp(argv[i], "--exit") && i + 1 < argc) exit_mode = argv[i + 1];
    if (!strcmp(argv[i], "--fork")) do_fork = true;
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
  if (!strcmp(exit_mode, "_exit")) _exit(rc);
  if (!strcmp(exit_mode, "sigterm")) raise(SIGTERM);
  return rc;
}
