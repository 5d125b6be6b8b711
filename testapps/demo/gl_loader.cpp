#include <GL/glew.h>

#include <stdexcept>
#include <string>

#include "context.hpp"

namespace demo {

void load_gl_functions(bool egl_context) {
  glewExperimental = GL_TRUE;  // core profiles: load entry points whatever the extension string says
  const GLenum status = glewInit();
  // Debian's GLEW is built for GLX: with an EGL context it loads the GL entry points, then
  // fails looking for a GLX display. That is success for our purposes.
  const bool ok = status == GLEW_OK || (egl_context && status == GLEW_ERROR_NO_GLX_DISPLAY);
  if (!ok) {
    throw std::runtime_error("glewInit failed: " +
                             std::string(reinterpret_cast<const char*>(glewGetErrorString(status))));
  }
  if (!glGenVertexArrays || !glDrawBuffers || !glVertexAttribIPointer) {
    throw std::runtime_error("the context lacks OpenGL 3.3 entry points");
  }
}

}  // namespace demo
