// An OpenGL 3.3 core context made current on this thread, with a default framebuffer of the
// requested size: an EGL pbuffer on the surfaceless platform (headless, the default) or a
// GLX window under X. Its GL entry points are loaded (GLEW) before the factory returns.
#pragma once
#include <memory>

namespace demo {

class GlContext {
 public:
  virtual ~GlContext() = default;
  virtual void swap_buffers() = 0;
  virtual const char* kind() const = 0;  // "egl-surfaceless" or "glx"
};

// Both throw std::runtime_error saying what failed.
std::unique_ptr<GlContext> create_egl_context(int width, int height);
std::unique_ptr<GlContext> create_glx_context(int width, int height);

// Loads GL entry points through GLEW for the current context (throws on failure).
void load_gl_functions(bool egl_context);

}  // namespace demo
