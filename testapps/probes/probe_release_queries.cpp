// An app that releases its context in the middle of a frame, as SDL does before it destroys a
// context: pass A is drawn, the context is made not current and current again, pass B ends the
// frame. It asks the driver itself, past any interposer, how many queries are active on the
// pipeline-statistics targets, once in the middle of pass A's frame and once after the
// release. Prints "active mid-frame: N" and "active after release: M" on stdout.
//
// Why it matters: llvmpipe frees a query that is still active when its context is destroyed
// without waiting for the rasterizer threads that write it; Warzone 2100 corrupted its heap at
// exit that way under an interposer that kept its queries open across the release.
#include <dlfcn.h>

#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

namespace {
using GetQueryiv = void (*)(GLenum, GLenum, GLint*);

// The driver's own entry: Mesa's glapi stub, which dispatches to the current context's table.
// dlsym of a GL name would reach an interposer's hook, which hides its own queries.
GetQueryiv driver_get_queryiv() {
  using GetProc = void* (*)(const char*);
  for (const char* lib : {"libglapi.so.0", "libGLdispatch.so.0"}) {
    void* h = dlopen(lib, RTLD_NOW | RTLD_NOLOAD);
    if (!h) continue;
    for (const char* entry : {"_glapi_get_proc_address", "__glDispatchGetProcAddress"}) {
      if (auto get = reinterpret_cast<GetProc>(dlsym(h, entry))) {
        if (void* fn = get("glGetQueryiv")) return reinterpret_cast<GetQueryiv>(fn);
      }
    }
  }
  return nullptr;
}

int active_statistics_queries(GetQueryiv get) {
  const GLenum targets[] = {GL_VERTEX_SHADER_INVOCATIONS_ARB, GL_FRAGMENT_SHADER_INVOCATIONS_ARB,
                            GL_PRIMITIVES_SUBMITTED_ARB, GL_VERTICES_SUBMITTED_ARB, GL_PRIMITIVES_GENERATED};
  int active = 0;
  for (GLenum t : targets) {
    GLint current = 0;
    get(t, GL_CURRENT_QUERY, &current);
    if (current != 0) ++active;
  }
  return active;
}
}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_release_queries", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  GlFns gl;
  gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); });
  KnownScene scene(gl, ShaderDialect::kGlsl330Core, args.width, args.height);
  if (!scene.ok()) return 2;
  GetQueryiv driver = driver_get_queryiv();
  if (!driver) {
    fprintf(stderr, "probe_release_queries: no glapi entry to ask the driver\n");
    return 2;
  }
  int mid_frame = 0, after_release = 0;
  for (int f = 0; f < args.frames; ++f) {
    gl.ClearColor(0, 0, 0, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    scene.draw_pass_a();
    mid_frame = active_statistics_queries(driver);
    egl.MakeCurrent(w.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    egl.MakeCurrent(w.display, w.surface, w.surface, w.context);
    after_release = active_statistics_queries(driver);
    scene.draw_pass_b();
    egl.SwapBuffers(w.display, w.surface);
  }
  printf("active mid-frame: %d\nactive after release: %d\n", mid_frame, after_release);
  if (!args.out.empty() && !write_ppm(args.out, scene.read_rgba(), args.width, args.height)) return 3;
  egl.MakeCurrent(w.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  egl.DestroyContext(w.display, w.context);
  egl.Terminate(w.display);
  return 0;
}
