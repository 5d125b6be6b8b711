// A GLX window under X (run it under Xvfb): glXCreateContextAttribsARB and every GL function
// from glXGetProcAddressARB, as GLFW and SDL do on X11.
#include <GL/glx.h>
#include <X11/Xlib.h>

#include <cstdio>

#include "common/probe_main.hpp"

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Display* dpy = XOpenDisplay(nullptr);
  if (!dpy) {
    fprintf(stderr, "probe_glx: cannot open X display\n");
    return 2;
  }
  const int fb_attribs[] = {GLX_X_RENDERABLE,
                            True,
                            GLX_DRAWABLE_TYPE,
                            GLX_WINDOW_BIT,
                            GLX_RENDER_TYPE,
                            GLX_RGBA_BIT,
                            GLX_RED_SIZE,
                            8,
                            GLX_GREEN_SIZE,
                            8,
                            GLX_BLUE_SIZE,
                            8,
                            GLX_DOUBLEBUFFER,
                            True,
                            None};
  int n = 0;
  GLXFBConfig* configs = glXChooseFBConfig(dpy, DefaultScreen(dpy), fb_attribs, &n);
  if (!configs || n < 1) {
    fprintf(stderr, "probe_glx: no GLX config\n");
    return 2;
  }
  XVisualInfo* vi = glXGetVisualFromFBConfig(dpy, configs[0]);
  XSetWindowAttributes swa{};
  swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
  Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, args.width, args.height, 0, vi->depth, InputOutput,
                             vi->visual, CWColormap, &swa);
  XMapWindow(dpy, win);
  using CreateAttribs = GLXContext (*)(Display*, GLXFBConfig, GLXContext, Bool, const int*);
  auto create = reinterpret_cast<CreateAttribs>(glXGetProcAddressARB((const GLubyte*)"glXCreateContextAttribsARB"));
  const int ctx_attribs[] = {
      GLX_CONTEXT_MAJOR_VERSION_ARB,    3,   GLX_CONTEXT_MINOR_VERSION_ARB, 3, GLX_CONTEXT_PROFILE_MASK_ARB,
      GLX_CONTEXT_CORE_PROFILE_BIT_ARB, None};
  GLXContext ctx = create ? create(dpy, configs[0], nullptr, True, ctx_attribs) : nullptr;
  if (!ctx) {
    fprintf(stderr, "probe_glx: cannot create a GL 3.3 core context\n");
    return 2;
  }
  glXMakeCurrent(dpy, win, ctx);
  GlFns gl;
  if (const char* missing = gl.load([](const char* n) { return (void*)glXGetProcAddressARB((const GLubyte*)n); })) {
    fprintf(stderr, "probe_glx: no %s\n", missing);
    return 2;
  }
  int rc = run_known_scene(gl, ShaderDialect::kGlsl330Core, args, [&] { glXSwapBuffers(dpy, win); });
  glXMakeCurrent(dpy, None, nullptr);
  glXDestroyContext(dpy, ctx);
  XDestroyWindow(dpy, win);
  XFree(vi);
  XFree(configs);
  XCloseDisplay(dpy);
  return rc;
}
