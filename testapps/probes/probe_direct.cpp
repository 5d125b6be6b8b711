// Links libEGL and libOpenGL and calls GL functions directly: symbol interposition.
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>

#include "common/egl_setup.h"
#include "common/probe_main.h"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  egl.load_linked();
  EglWindow w;
  std::string error;
  if (!egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &w, &error)) {
    fprintf(stderr, "probe_direct: %s\n", error.c_str());
    return 2;
  }
  eglMakeCurrent(w.display, w.surface, w.surface, w.context);
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
