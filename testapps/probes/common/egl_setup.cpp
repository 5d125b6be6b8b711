#include "egl_setup.hpp"

#include <cstdio>

void EglFns::load_linked() {
  GetPlatformDisplayEXT =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  Initialize = &eglInitialize;
  BindAPI = &eglBindAPI;
  ChooseConfig = &eglChooseConfig;
  CreateContext = &eglCreateContext;
  CreatePbufferSurface = &eglCreatePbufferSurface;
  MakeCurrent = &eglMakeCurrent;
  SwapBuffers = &eglSwapBuffers;
  DestroyContext = &eglDestroyContext;
  DestroySurface = &eglDestroySurface;
  Terminate = &eglTerminate;
  GetProcAddress = &eglGetProcAddress;
  ReleaseThread = &eglReleaseThread;
}

bool EglFns::load_with(void* (*lookup)(void*, const char*), void* h) {
#define LOAD(field, name) field = reinterpret_cast<decltype(field)>(lookup(h, name))
  LOAD(Initialize, "eglInitialize");
  LOAD(BindAPI, "eglBindAPI");
  LOAD(ChooseConfig, "eglChooseConfig");
  LOAD(CreateContext, "eglCreateContext");
  LOAD(CreatePbufferSurface, "eglCreatePbufferSurface");
  LOAD(MakeCurrent, "eglMakeCurrent");
  LOAD(SwapBuffers, "eglSwapBuffers");
  LOAD(DestroyContext, "eglDestroyContext");
  LOAD(DestroySurface, "eglDestroySurface");
  LOAD(Terminate, "eglTerminate");
  LOAD(GetProcAddress, "eglGetProcAddress");
  LOAD(ReleaseThread, "eglReleaseThread");
#undef LOAD
  if (!GetProcAddress) return false;
  GetPlatformDisplayEXT = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(GetProcAddress("eglGetPlatformDisplayEXT"));
  return Initialize && MakeCurrent && SwapBuffers && CreateContext && GetPlatformDisplayEXT;
}

bool egl_create(const EglFns& egl, ContextKind kind, int width, int height, EGLContext share, EglWindow* out,
                std::string* error, EGLDisplay reuse_display) {
  EglWindow w;
  w.display = reuse_display;
  if (w.display == EGL_NO_DISPLAY) {
    w.display = egl.GetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (w.display == EGL_NO_DISPLAY || !egl.Initialize(w.display, nullptr, nullptr)) {
      *error = "no surfaceless EGL display";
      return false;
    }
  }
  const bool gles = kind == ContextKind::kGles2 || kind == ContextKind::kGles3;
  egl.BindAPI(gles ? EGL_OPENGL_ES_API : EGL_OPENGL_API);
  const EGLint renderable = kind == ContextKind::kGles2   ? EGL_OPENGL_ES2_BIT
                            : kind == ContextKind::kGles3 ? EGL_OPENGL_ES3_BIT
                                                          : EGL_OPENGL_BIT;
  const EGLint config_attribs[] = {
      EGL_SURFACE_TYPE,    EGL_PBUFFER_BIT, EGL_RED_SIZE, 8, EGL_GREEN_SIZE, 8, EGL_BLUE_SIZE, 8, EGL_ALPHA_SIZE, 8,
      EGL_RENDERABLE_TYPE, renderable,      EGL_NONE};
  EGLint n = 0;
  if (!egl.ChooseConfig(w.display, config_attribs, &w.config, 1, &n) || n < 1) {
    *error = "no EGL config";
    return false;
  }
  const EGLint pbuffer_attribs[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
  w.surface = egl.CreatePbufferSurface(w.display, w.config, pbuffer_attribs);
  EGLint ctx_attribs[9];
  int i = 0;
  switch (kind) {
    case ContextKind::kCore45:
      ctx_attribs[i++] = EGL_CONTEXT_MAJOR_VERSION;
      ctx_attribs[i++] = 4;
      ctx_attribs[i++] = EGL_CONTEXT_MINOR_VERSION;
      ctx_attribs[i++] = 5;
      ctx_attribs[i++] = EGL_CONTEXT_OPENGL_PROFILE_MASK;
      ctx_attribs[i++] = EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT;
      break;
    case ContextKind::kCompat:
      ctx_attribs[i++] = EGL_CONTEXT_OPENGL_PROFILE_MASK;
      ctx_attribs[i++] = EGL_CONTEXT_OPENGL_COMPATIBILITY_PROFILE_BIT;
      break;
    case ContextKind::kGles2:
      ctx_attribs[i++] = EGL_CONTEXT_MAJOR_VERSION;
      ctx_attribs[i++] = 2;
      break;
    case ContextKind::kGles3:
      ctx_attribs[i++] = EGL_CONTEXT_MAJOR_VERSION;
      ctx_attribs[i++] = 3;
      break;
  }
  ctx_attribs[i] = EGL_NONE;
  w.context = egl.CreateContext(w.display, w.config, share, ctx_attribs);
  if (w.context == EGL_NO_CONTEXT || w.surface == EGL_NO_SURFACE) {
    *error = "cannot create EGL context or pbuffer";
    return false;
  }
  *out = w;
  return true;
}

bool open_current_window(const char* probe, EglFns& egl, ContextKind kind, int width, int height, EglWindow* out) {
  egl.load_linked();
  std::string error;
  if (!egl_create(egl, kind, width, height, EGL_NO_CONTEXT, out, &error)) {
    fprintf(stderr, "%s: %s\n", probe, error.c_str());
    return false;
  }
  egl.MakeCurrent(out->display, out->surface, out->surface, out->context);
  return true;
}
