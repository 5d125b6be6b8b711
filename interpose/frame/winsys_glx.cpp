// GLX entry points: context life cycle, frame boundaries, GetProcAddress interception.
#include <GL/glx.h>

#include "context_state.hpp"
#include "frame_output.hpp"
#include "hook_table.hpp"
#include "proc_address.hpp"

using namespace glbudget;

GLBUDGET_EXPORT __GLXextFuncPtr glXGetProcAddressARB(const GLubyte* name) {
  auto fn = real_function<__GLXextFuncPtr (*)(const GLubyte*)>(kHook_glXGetProcAddressARB);
  if (!fn) return nullptr;
  auto p = reinterpret_cast<void*>(fn(name));
  return reinterpret_cast<__GLXextFuncPtr>(hook_for_proc(reinterpret_cast<const char*>(name), p));
}

GLBUDGET_EXPORT __GLXextFuncPtr glXGetProcAddress(const GLubyte* name) {
  auto fn = real_function<__GLXextFuncPtr (*)(const GLubyte*)>(kHook_glXGetProcAddress);
  if (!fn) return nullptr;
  auto p = reinterpret_cast<void*>(fn(name));
  return reinterpret_cast<__GLXextFuncPtr>(hook_for_proc(reinterpret_cast<const char*>(name), p));
}

GLBUDGET_EXPORT GLXContext glXCreateContext(Display* dpy, XVisualInfo* vis, GLXContext share, Bool direct) {
  auto fn = real_function<decltype(&glXCreateContext)>(kHook_glXCreateContext);
  if (!fn) return nullptr;
  GLXContext c = fn(dpy, vis, share, direct);
  context_created(c, dpy, share);
  return c;
}

GLBUDGET_EXPORT GLXContext glXCreateNewContext(Display* dpy, GLXFBConfig config, int type, GLXContext share,
                                               Bool direct) {
  auto fn = real_function<decltype(&glXCreateNewContext)>(kHook_glXCreateNewContext);
  if (!fn) return nullptr;
  GLXContext c = fn(dpy, config, type, share, direct);
  context_created(c, dpy, share);
  return c;
}

GLBUDGET_EXPORT GLXContext glXCreateContextAttribsARB(Display* dpy, GLXFBConfig config, GLXContext share, Bool direct,
                                                      const int* attribs) {
  using Fn = GLXContext (*)(Display*, GLXFBConfig, GLXContext, Bool, const int*);
  auto fn = real_function<Fn>(kHook_glXCreateContextAttribsARB);
  if (!fn) return nullptr;
  GLXContext c = fn(dpy, config, share, direct, attribs);
  context_created(c, dpy, share);
  return c;
}

GLBUDGET_EXPORT Bool glXMakeCurrent(Display* dpy, GLXDrawable drawable, GLXContext ctx) {
  auto fn = real_function<decltype(&glXMakeCurrent)>(kHook_glXMakeCurrent);
  if (!fn) return False;
  context_will_change(ctx);
  Bool ok = fn(dpy, drawable, ctx);
  if (ok) context_made_current(ctx, dpy, false);
  return ok;
}

GLBUDGET_EXPORT Bool glXMakeContextCurrent(Display* dpy, GLXDrawable draw, GLXDrawable read, GLXContext ctx) {
  auto fn = real_function<decltype(&glXMakeContextCurrent)>(kHook_glXMakeContextCurrent);
  if (!fn) return False;
  context_will_change(ctx);
  Bool ok = fn(dpy, draw, read, ctx);
  if (ok) context_made_current(ctx, dpy, false);
  return ok;
}

GLBUDGET_EXPORT void glXDestroyContext(Display* dpy, GLXContext ctx) {
  auto fn = real_function<decltype(&glXDestroyContext)>(kHook_glXDestroyContext);
  if (!fn) return;
  context_destroyed(ctx);
  fn(dpy, ctx);
}

GLBUDGET_EXPORT void glXSwapBuffers(Display* dpy, GLXDrawable drawable) {
  auto fn = real_function<decltype(&glXSwapBuffers)>(kHook_glXSwapBuffers);
  if (!fn) return;
  swap_begin();
  fn(dpy, drawable);
  swap_end();
}
