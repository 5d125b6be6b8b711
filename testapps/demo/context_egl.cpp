#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "context.hpp"
#include "headless_egl.hpp"

namespace demo {
namespace {

class EglContext : public GlContext {
 public:
  EglContext(int width, int height) {
    // No display server needed: llvmpipe works, and so does NVIDIA's device platform.
    const testapps::HeadlessDisplay headless = testapps::open_headless_egl_display();
    display_ = headless.display;
    platform_ = headless.platform;
    if (display_ == EGL_NO_DISPLAY) fail("eglInitialize (no surfaceless, device or default EGL display)");
    const EGLint config_attributes[] = {EGL_SURFACE_TYPE,
                                        EGL_PBUFFER_BIT,
                                        EGL_RENDERABLE_TYPE,
                                        EGL_OPENGL_BIT,
                                        EGL_RED_SIZE,
                                        8,
                                        EGL_GREEN_SIZE,
                                        8,
                                        EGL_BLUE_SIZE,
                                        8,
                                        EGL_ALPHA_SIZE,
                                        8,
                                        EGL_NONE};
    EGLConfig config = nullptr;
    EGLint count = 0;
    if (!eglChooseConfig(display_, config_attributes, &config, 1, &count) || count == 0) fail("eglChooseConfig");
    const EGLint surface_attributes[] = {EGL_WIDTH, width, EGL_HEIGHT, height, EGL_NONE};
    surface_ = eglCreatePbufferSurface(display_, config, surface_attributes);
    if (surface_ == EGL_NO_SURFACE) fail("eglCreatePbufferSurface");
    if (!eglBindAPI(EGL_OPENGL_API)) fail("eglBindAPI");
    const EGLint context_attributes[] = {
        EGL_CONTEXT_MAJOR_VERSION,           3,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
        EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context_ = eglCreateContext(display_, config, EGL_NO_CONTEXT, context_attributes);
    if (context_ == EGL_NO_CONTEXT) fail("eglCreateContext (OpenGL 3.3 core)");
    if (!eglMakeCurrent(display_, surface_, surface_, context_)) fail("eglMakeCurrent");
  }

  ~EglContext() override { release(); }

  // A pbuffer has nothing to present, but the swap still marks the end of the frame for
  // anything watching the process.
  void swap_buffers() override { eglSwapBuffers(display_, surface_); }
  const char* kind() const override { return platform_; }

 private:
  [[noreturn]] void fail(const char* what) {
    const std::string message = std::string(what) + " failed (EGL error 0x" + to_hex(eglGetError()) + ")";
    release();  // the destructor does not run when the constructor throws
    throw std::runtime_error(message);
  }
  void release() {
    if (display_ == EGL_NO_DISPLAY) return;
    eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
    if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
    eglTerminate(display_);
    display_ = EGL_NO_DISPLAY;
  }
  static std::string to_hex(EGLint value) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "%04x", static_cast<unsigned>(value));
    return buffer;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  const char* platform_ = "egl";
  EGLSurface surface_ = EGL_NO_SURFACE;
  EGLContext context_ = EGL_NO_CONTEXT;
};

}  // namespace

std::unique_ptr<GlContext> create_egl_context(int width, int height) {
  auto context = std::make_unique<EglContext>(width, height);
  load_gl_functions(true);
  return context;
}

}  // namespace demo
