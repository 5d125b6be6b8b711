// A context destroyed in the middle of a frame, while it is current: the fourth frame draws
// pass A and pass B and then, without a swap, the context goes and a new one (sharing nothing)
// takes over for the frames left. Under the shim with quality probes every other frame, the
// fourth is a probe frame, so the probe's shadow targets and read-backs vanish with it.
#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  constexpr int kDestroyAt = 3;  // 0-based: the fourth frame
  EglFns egl;
  egl.load_linked();
  EglWindow first, second;
  std::string error;
  if (!egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &first, &error)) {
    fprintf(stderr, "probe_destroy_mid_frame: %s\n", error.c_str());
    return 2;
  }
  GlFns gl;
  egl.MakeCurrent(first.display, first.surface, first.surface, first.context);
  gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); });
  auto* scene = new KnownScene(gl, ShaderDialect::kGlsl330Core, args.width, args.height);
  if (!scene->ok()) return 2;
  EglWindow* current = &first;
  for (int f = 0; f < args.frames; ++f) {
    scene->draw_frame(f);
    if (f != kDestroyAt) {
      egl.SwapBuffers(current->display, current->surface);
      continue;
    }
    // The scene's objects go with the context; only the memory of its wrapper is ours to free.
    delete scene;
    egl.DestroyContext(first.display, first.context);
    egl.MakeCurrent(first.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (!egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &second, &error,
                    first.display)) {
      fprintf(stderr, "probe_destroy_mid_frame: %s\n", error.c_str());
      return 2;
    }
    egl.MakeCurrent(second.display, second.surface, second.surface, second.context);
    current = &second;
    scene = new KnownScene(gl, ShaderDialect::kGlsl330Core, args.width, args.height);
    if (!scene->ok()) return 2;
  }
  if (!write_ppm(args.out, scene->read_rgba(), args.width, args.height)) return 3;
  delete scene;
  egl.DestroyContext(second.display, second.context);
  egl.MakeCurrent(first.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  egl.Terminate(first.display);
  return 0;
}
