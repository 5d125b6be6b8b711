// Links only libEGL and takes every GL function from eglGetProcAddress (glad, epoxy style).
// --es 2|3 asks for a GLES context instead of GL 4.5 core.
#include <cstdio>
#include <cstring>

#include "common/egl_setup.hpp"
#include "common/probe_main.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  int es = 0;
  for (int i = 1; i + 1 < argc; ++i)
    if (!strcmp(argv[i], "--es")) es = atoi(argv[i + 1]);
  ContextKind kind = es == 2 ? ContextKind::kGles2 : es == 3 ? ContextKind::kGles3 : ContextKind::kCore45;
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_getproc", egl, kind, args.width, args.height, &w)) return 2;
  GlFns gl;
  if (const char* missing = gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); })) {
    fprintf(stderr, "probe_getproc: no %s\n", missing);
    return 2;
  }
  ShaderDialect dialect = es == 2   ? ShaderDialect::kEssl100
                          : es == 3 ? ShaderDialect::kEssl300
                                    : ShaderDialect::kGlsl330Core;
  return run_known_scene(gl, dialect, args, [&] { egl.SwapBuffers(w.display, w.surface); });
}
