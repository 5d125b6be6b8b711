// Two threads, each with its own context current, render concurrently; then the first
// context is made current on the main thread and swapped once more with no draw.
#include <cstdio>
#include <thread>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  egl.load_linked();
  EglWindow w[2];
  std::string error;
  if (!egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &w[0], &error) ||
      !egl_create(egl, ContextKind::kCore45, args.width, args.height, EGL_NO_CONTEXT, &w[1], &error, w[0].display)) {
    fprintf(stderr, "probe_threads: %s\n", error.c_str());
    return 2;
  }
  int rc[2] = {0, 0};
  std::vector<uint8_t> image;
  auto render = [&](int i) {
    egl.MakeCurrent(w[i].display, w[i].surface, w[i].surface, w[i].context);
    GlFns gl;
    gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); });
    KnownScene scene(gl, ShaderDialect::kGlsl330Core, args.width, args.height);
    if (!scene.ok()) {
      rc[i] = 2;
      return;
    }
    for (int f = 0; f < args.frames; ++f) {
      scene.draw_frame(f);
      egl.SwapBuffers(w[i].display, w[i].surface);
    }
    if (i == 0) image = scene.read_rgba();
    egl.ReleaseThread();
  };
  std::thread t0(render, 0), t1(render, 1);
  t0.join();
  t1.join();
  // A swap with no context current on this thread must pass through untouched.
  egl.SwapBuffers(w[0].display, w[0].surface);
  if (rc[0] || rc[1]) return 2;
  if (!write_ppm(args.out, image, args.width, args.height)) return 3;
  return 0;
}
