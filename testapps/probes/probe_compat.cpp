// Compatibility profile: a GLSL 1.20 pass, fixed-function glBegin/glEnd quads and a display
// list. Per frame: pass A and B as in the known scene, then a fixed-function pass of
// 2 batches (two glBegin quads) + 1 (the list call); the list compiled once in GL_COMPILE
// mode draws nothing when compiled and must not be counted then.
// --push-attrib 1: the fixed-function quads drawn as a HUD is, between glPushAttrib(GL_ALL_
// ATTRIB_BITS) and glPopAttrib with a viewport and scissor box of their own (SFML's
// pushGLStates, older engines' overlays), and every other frame a push made before the swap
// popped after it, the window bound again first. After each pop GL_VIEWPORT must be the app's
// again (else exit 5), and no GL error may have been raised (else exit 4).
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  bool push_attrib = false;
  for (int i = 1; i + 1 < argc; ++i)
    if (!strcmp(argv[i], "--push-attrib")) push_attrib = atoi(argv[i + 1]) != 0;
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
  auto viewport_is_the_apps = [&] {
    GLint v[4] = {};
    glGetIntegerv(GL_VIEWPORT, v);
    return v[0] == 0 && v[1] == 0 && v[2] == args.width && v[3] == args.height;
  };
  if (push_attrib) {
    // Named as apps name them (SDL and engines set both at start).
    glDrawBuffer(GL_BACK);
    glReadBuffer(GL_BACK);
  }
  for (int f = 0; f < args.frames; ++f) {
    const bool across_swap = push_attrib && f % 2 == 1;
    scene.draw_frame(f);
    if (across_swap) {
      // Popped with the window bound, after this frame has drawn into it (extremetuxracer): the
      // read and draw buffers pushed name the window as it was before the swap.
      glBindFramebuffer(GL_FRAMEBUFFER, 0);
      glPopAttrib();  // pushed before the last swap
    }
    if (push_attrib && !viewport_is_the_apps()) return 5;
    gl.UseProgram(0);
    if (push_attrib) {
      glPushAttrib(GL_ALL_ATTRIB_BITS);
      glViewport(args.width / 2, 0, args.width / 2, args.height / 2);
      glScissor(args.width / 2, 0, args.width / 2, args.height / 2);
      glEnable(GL_SCISSOR_TEST);
    }
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
    if (push_attrib) {
      glPopAttrib();
      if (!viewport_is_the_apps()) return 5;
      if (f % 2 == 0) glPushAttrib(GL_VIEWPORT_BIT | GL_PIXEL_MODE_BIT | GL_COLOR_BUFFER_BIT);
    }
    eglSwapBuffers(w.display, w.surface);
  }
  if (push_attrib && args.frames % 2 == 1) glPopAttrib();
  if (push_attrib && glGetError() != GL_NO_ERROR) return 4;
  if (!write_ppm(args.out, scene.read_rgba(), args.width, args.height)) return 3;
  return 0;
}
