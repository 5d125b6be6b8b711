// Compatibility profile: a GLSL 1.20 pass, fixed-function glBegin/glEnd quads and a display
// list. Per frame: pass A and B as in the known scene, then a fixed-function pass of
// 2 batches (two glBegin quads) + 1 (the list call); the list compiled once in GL_COMPILE
// mode draws nothing when compiled and must not be counted then.
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_compat", egl, ContextKind::kCompat, args.width, args.height, &w)) return 2;
  GlFns gl;
  if (const char* missing = gl.load([&](const char* n) { return (void*)eglGetProcAddress(n); })) {
    fprintf(stderr, "probe_compat: no %s\n", missing);
    return 2;
  }
  KnownScene scene(gl, ShaderDialect::kGlsl120Compat, args.width, args.height);
  if (!scene.ok()) {
    fprintf(stderr, "probe_compat: %s\n", scene.error().c_str());
    return 2;
  }
  GLuint list = glGenLists(1);
  glNewList(list, GL_COMPILE);
  glColor3f(0.3f, 0.3f, 0.9f);
  glBegin(GL_QUADS);
  glVertex2f(-0.5f, -1);
  glVertex2f(0, -1);
  glVertex2f(0, -0.5f);
  glVertex2f(-0.5f, -0.5f);
  glEnd();
  glEndList();
  for (int f = 0; f < args.frames; ++f) {
    scene.draw_frame(f);
    gl.UseProgram(0);
    for (int q = 0; q < 2; ++q) {
      glColor3f(1, 0.5f * q, 0);
      glBegin(GL_QUADS);
      glVertex2f(0.5f, -1);
      glVertex2f(1, -1);
      glVertex2f(1, -0.5f + 0.25f * q);
      glVertex2f(0.5f, -0.5f + 0.25f * q);
      glEnd();
    }
    glCallList(list);
    eglSwapBuffers(w.display, w.surface);
  }
  if (!write_ppm(args.out, scene.read_rgba(), args.width, args.height)) return 3;
  return 0;
}
