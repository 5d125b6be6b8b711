// Loads GL through GLEW (which asks glXGetProcAddressARB) on an EGL surfaceless context.
#include <GL/glew.h>

#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/probe_main.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_glew", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  glewExperimental = GL_TRUE;
  GLenum r = glewInit();
  // Debian's GLEW is built for GLX: with an EGL context it loads the GL entry points and then
  // reports that it found no GLX display (GLEW_ERROR_NO_GLX_DISPLAY), which is harmless here.
  if (r != GLEW_OK && r != GLEW_ERROR_NO_GLX_DISPLAY) {
    fprintf(stderr, "probe_glew: glewInit failed (%u)\n", r);
    return 2;
  }
  GlFns gl;
#define FROM_GLEW(type, name) gl.name = gl##name;
  PROBE_GL_FUNCTIONS(FROM_GLEW)
#undef FROM_GLEW
  return run_known_scene(gl, ShaderDialect::kGlsl330Core, args, [&] { egl.SwapBuffers(w.display, w.surface); });
}
