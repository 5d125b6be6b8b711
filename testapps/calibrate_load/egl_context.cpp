#include "egl_context.hpp"

#include <EGL/eglext.h>
#include <GL/glew.h>

#include <cstdio>
#include <stdexcept>
#include <string>

#include "headless_egl.hpp"

namespace calibrate_load {

EglContext::EglContext(int width, int height) {
  display_ = testapps::open_headless_egl_display().display;
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
  glewExperimental = GL_TRUE;  // a core profile: load entry points whatever the extension string says
  const GLenum status = glewInit();
  // Debian's GLEW is built for GLX: with an EGL context it loads GL, then fails to find a GLX display.
  if (status != GLEW_OK && status != GLEW_ERROR_NO_GLX_DISPLAY) fail("glewInit");
  if (!glGenVertexArrays || !glFenceSync || !glUniform1i) fail("loading OpenGL 3.3 entry points");
}

EglContext::~EglContext() { release(); }

void EglContext::swap_buffers() { eglSwapBuffers(display_, surface_); }

void EglContext::fail(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "%04x", static_cast<unsigned>(eglGetError()));
  release();  // the destructor does not run when the constructor throws
  throw std::runtime_error(std::string(what) + " failed (EGL error 0x" + code + ")");
}

void EglContext::release() {
  if (display_ == EGL_NO_DISPLAY) return;
  eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (context_ != EGL_NO_CONTEXT) eglDestroyContext(display_, context_);
  if (surface_ != EGL_NO_SURFACE) eglDestroySurface(display_, surface_);
  eglTerminate(display_);
  display_ = EGL_NO_DISPLAY;
}

}  // namespace calibrate_load
