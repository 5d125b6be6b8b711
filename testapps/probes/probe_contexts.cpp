// Three contexts on one thread: B shares objects with A, C shares nothing. Each frame every
// context draws the known scene and swaps, so each has its own frames and query pools, and
// the same sources give the same pass names everywhere. Context i draws the scene's frame
// f + i at its frame f: the same frame number shows a different image in each context.
#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  egl.load_linked();
  EglWindow a, b, c;
  std::string error;
  if (!egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &a, &error) ||
      !egl_create(egl, ContextKind::kCore45, args.width, args.height, a.context, &b, &error, a.display) ||
      !egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &c, &error, a.display)) {
    fprintf(stderr, "probe_contexts: %s\n", error.c_str());
    return 2;
  }
  GlFns gl;
  egl.MakeCurrent(a.display, a.surface, a.surface, a.context);
  gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); });
  EglWindow* wins[3] = {&a, &b, &c};
  KnownScene* scenes[3];
  for (int i = 0; i < 3; ++i) {
    egl.MakeCurrent(a.display, wins[i]->surface, wins[i]->surface, wins[i]->context);
    scenes[i] = new KnownScene(gl, ShaderDialect::kGlsl330Core, args.width, args.height);
    if (!scenes[i]->ok()) return 2;
  }
  for (int f = 0; f < args.frames; ++f) {
    for (int i = 0; i < 3; ++i) {
      egl.MakeCurrent(a.display, wins[i]->surface, wins[i]->surface, wins[i]->context);
      scenes[i]->draw_frame(f + i);
      egl.SwapBuffers(a.display, wins[i]->surface);
      gl.Finish();  // complete this context's work before another context touches shared objects
    }
  }
  egl.MakeCurrent(a.display, c.surface, c.surface, c.context);
  if (!write_ppm(args.out, scenes[2]->read_rgba(), args.width, args.height)) return 3;
  // Destroy one context while another is current, and one while it is current.
  egl.DestroyContext(a.display, b.context);
  egl.DestroyContext(a.display, c.context);
  egl.MakeCurrent(a.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  egl.Terminate(a.display);
  return 0;
}
