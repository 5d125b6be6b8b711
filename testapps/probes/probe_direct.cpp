// Links libEGL and libOpenGL and calls GL functions directly: symbol interposition.
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/probe_main.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_direct", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  GlFns gl;
#define DIRECT(type, name) gl.name = &::gl##name;
  PROBE_GL_FUNCTIONS(DIRECT)
#undef DIRECT
  int rc = run_known_scene(gl, ShaderDialect::kGlsl330Core, args, [&] { eglSwapBuffers(w.display, w.surface); });
  eglMakeCurrent(w.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(w.display, w.context);
  eglTerminate(w.display);
  return rc;
}
