// EGL entry points: context life cycle, frame boundaries, GetProcAddress interception.
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "context_state.hpp"
#include "frame_output.hpp"
#include "hook_table.hpp"
#include "proc_address.hpp"

using namespace glbudget;

GLBUDGET_EXPORT __eglMustCastToProperFunctionPointerType eglGetProcAddress(const char* name) {
  auto fn = real_function<decltype(&eglGetProcAddress)>(kHook_eglGetProcAddress);
  if (!fn) return nullptr;
  auto p = reinterpret_cast<void*>(fn(name));
  return reinterpret_cast<__eglMustCastToProperFunctionPointerType>(hook_for_proc(name, p));
}

GLBUDGET_EXPORT EGLContext eglCreateContext(EGLDisplay dpy, EGLConfig config, EGLContext share, const EGLint* attribs) {
  auto fn = real_function<decltype(&eglCreateContext)>(kHook_eglCreateContext);
  if (!fn) return EGL_NO_CONTEXT;
  EGLContext c = fn(dpy, config, share, attribs);
  if (c != EGL_NO_CONTEXT) context_created(c, dpy, share);
  return c;
}

GLBUDGET_EXPORT EGLBoolean eglMakeCurrent(EGLDisplay dpy, EGLSurface draw, EGLSurface read, EGLContext ctx) {
  auto fn = real_function<decltype(&eglMakeCurrent)>(kHook_eglMakeCurrent);
  if (!fn) return EGL_FALSE;
  context_will_change(ctx);
  EGLBoolean ok = fn(dpy, draw, read, ctx);
  if (ok) context_made_current(ctx, dpy, true);
  return ok;
}

GLBUDGET_EXPORT EGLBoolean eglDestroyContext(EGLDisplay dpy, EGLContext ctx) {
  auto fn = real_function<decltype(&eglDestroyContext)>(kHook_eglDestroyContext);
  if (!fn) return EGL_FALSE;
  context_destroyed(ctx);
  return fn(dpy, ctx);
}

GLBUDGET_EXPORT EGLBoolean eglTerminate(EGLDisplay dpy) {
  auto fn = real_function<decltype(&eglTerminate)>(kHook_eglTerminate);
  if (!fn) return EGL_FALSE;
  display_terminated(dpy);
  return fn(dpy);
}

GLBUDGET_EXPORT EGLBoolean eglReleaseThread(void) {
  auto fn = real_function<decltype(&eglReleaseThread)>(kHook_eglReleaseThread);
  if (!fn) return EGL_FALSE;
  context_will_change(nullptr);
  EGLBoolean ok = fn();
  if (ok) context_made_current(nullptr, nullptr, true);
  return ok;
}

GLBUDGET_EXPORT EGLBoolean eglSwapBuffers(EGLDisplay dpy, EGLSurface surface) {
  auto fn = real_function<decltype(&eglSwapBuffers)>(kHook_eglSwapBuffers);
  if (!fn) return EGL_FALSE;
  swap_begin();
  EGLBoolean ok = fn(dpy, surface);
  swap_end();
  return ok;
}

// The KHR and EXT entry points have the same signature and the same meaning.
static EGLBoolean swap_with_damage(int hook, EGLDisplay dpy, EGLSurface surface, const EGLint* rects, EGLint n) {
  auto fn = real_function<PFNEGLSWAPBUFFERSWITHDAMAGEKHRPROC>(hook);
  if (!fn) return EGL_FALSE;
  swap_begin();
  EGLBoolean ok = fn(dpy, surface, rects, n);
  swap_end();
  return ok;
}

GLBUDGET_EXPORT EGLBoolean eglSwapBuffersWithDamageKHR(EGLDisplay dpy, EGLSurface surface, const EGLint* rects,
                                                       EGLint n) {
  return swap_with_damage(kHook_eglSwapBuffersWithDamageKHR, dpy, surface, rects, n);
}

GLBUDGET_EXPORT EGLBoolean eglSwapBuffersWithDamageEXT(EGLDisplay dpy, EGLSurface surface, const EGLint* rects,
                                                       EGLint n) {
  return swap_with_damage(kHook_eglSwapBuffersWithDamageEXT, dpy, surface, rects, n);
}
