// EGL surfaceless setup for the probes: a pbuffer surface and a context of the asked API.
// The EGL functions come through a lookup so that the dlopen probe can use dlsym for them too.
#pragma once
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <string>

enum class ContextKind { kCore45, kCompat, kGles2, kGles3 };

struct EglFns {
  PFNEGLGETPLATFORMDISPLAYEXTPROC GetPlatformDisplayEXT = nullptr;
  decltype(&eglInitialize) Initialize = nullptr;
  decltype(&eglBindAPI) BindAPI = nullptr;
  decltype(&eglChooseConfig) ChooseConfig = nullptr;
  decltype(&eglCreateContext) CreateContext = nullptr;
  decltype(&eglCreatePbufferSurface) CreatePbufferSurface = nullptr;
  decltype(&eglMakeCurrent) MakeCurrent = nullptr;
  decltype(&eglSwapBuffers) SwapBuffers = nullptr;
  decltype(&eglDestroyContext) DestroyContext = nullptr;
  decltype(&eglDestroySurface) DestroySurface = nullptr;
  decltype(&eglTerminate) Terminate = nullptr;
  decltype(&eglGetProcAddress) GetProcAddress = nullptr;
  decltype(&eglReleaseThread) ReleaseThread = nullptr;
  void load_linked();                                                 // the app linked libEGL
  bool load_with(void* (*lookup)(void*, const char*), void* handle);  // dlsym-style
};

struct EglWindow {
  EGLDisplay display = EGL_NO_DISPLAY;
  EGLConfig config = nullptr;
  EGLSurface surface = EGL_NO_SURFACE;
  EGLContext context = EGL_NO_CONTEXT;
};

// The usual opening of a probe: EGL from the linked libEGL, one pbuffer and context of `kind`,
// made current. On failure prints "<probe>: <reason>" on stderr and returns false.
bool open_current_window(const char* probe, EglFns& egl, ContextKind kind, int width, int height, EglWindow* out);

// Creates display, pbuffer and context (sharing with `share` if given); on failure returns
// false with a reason in `error`. Does not make it current.
bool egl_create(const EglFns& egl, ContextKind kind, int width, int height, EGLContext share, EglWindow* out,
                std::string* error, EGLDisplay reuse_display = EGL_NO_DISPLAY);
