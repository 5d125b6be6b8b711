// An OpenGL 3.3 core context on a headless EGL display (no display server; llvmpipe works),
// current on this thread, drawing into a pbuffer of the given size.
#pragma once
#include <EGL/egl.h>

namespace calibrate_load {

class EglContext {
 public:
  EglContext(int width, int height);  // throws std::runtime_error saying what failed
  ~EglContext();
  EglContext(const EglContext&) = delete;
  EglContext& operator=(const EglContext&) = delete;

  // A pbuffer presents nothing, but the swap ends the frame for whoever watches the process.
  void swap_buffers();

 private:
  [[noreturn]] void fail(const char* what);
  void release();

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLSurface surface_ = EGL_NO_SURFACE;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace calibrate_load
