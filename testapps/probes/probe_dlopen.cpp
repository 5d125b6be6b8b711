// Links no GL library at all: dlopens libEGL and libOpenGL and dlsyms every entry point from
// the handles (SDL, GLFW style), where preloading alone cannot interpose.
#include <dlfcn.h>

#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/probe_main.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  void* libegl = dlopen("libEGL.so.1", RTLD_NOW | RTLD_LOCAL);
  void* libgl = dlopen("libOpenGL.so.0", RTLD_NOW | RTLD_LOCAL);
  if (!libegl || !libgl) {
    fprintf(stderr, "probe_dlopen: %s\n", dlerror());
    return 2;
  }
  EglFns egl;
  if (!egl.load_with(&dlsym, libegl)) {
    fprintf(stderr, "probe_dlopen: EGL functions missing\n");
    return 2;
  }
  EglWindow w;
  std::string error;
  if (!egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &w, &error)) {
    fprintf(stderr, "probe_dlopen: %s\n", error.c_str());
    return 2;
  }
  egl.MakeCurrent(w.display, w.surface, w.surface, w.context);
  GlFns gl;
  if (const char* missing = gl.load([&](const char* n) { return dlsym(libgl, n); })) {
    fprintf(stderr, "probe_dlopen: no %s\n", missing);
    return 2;
  }
  return run_known_scene(gl, ShaderDialect::kGlsl330Core, args, [&] { egl.SwapBuffers(w.display, w.surface); });
}
