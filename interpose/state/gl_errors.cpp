#include "gl_errors.hpp"

#include <algorithm>
#include <cstdio>
#include <string>

#include "context_state.hpp"
#include "gl_calls.hpp"
#include "hooks_generated.hpp"

namespace glbudget {

std::vector<GLenum> drain_gl_errors() {
  std::vector<GLenum> errors;
  if (!gl().GetError) return errors;
  for (int reads = 0; reads < 8; ++reads) {
    const GLenum e = gl().GetError();
    if (e == GL_NO_ERROR) break;
    if (std::find(errors.begin(), errors.end(), e) == errors.end()) errors.push_back(e);
  }
  return errors;
}

std::string gl_error_name(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM:
      return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE:
      return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION:
      return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION:
      return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY:
      return "GL_OUT_OF_MEMORY";
    case GL_STACK_OVERFLOW:
      return "GL_STACK_OVERFLOW";
    case GL_STACK_UNDERFLOW:
      return "GL_STACK_UNDERFLOW";
    case GL_CONTEXT_LOST:
      return "GL_CONTEXT_LOST";
    default: {
      char hex[16];
      std::snprintf(hex, sizeof hex, "0x%04x", error);
      return hex;
    }
  }
}

void keep_app_errors(ContextState& c) {
  for (GLenum e : drain_gl_errors())
    if (std::find(c.app_errors.begin(), c.app_errors.end(), e) == c.app_errors.end()) c.app_errors.push_back(e);
}

OwnGlWork::OwnGlWork(ContextState& c) : c_(c) { keep_app_errors(c_); }

OwnGlWork::~OwnGlWork() { drain_gl_errors(); }

// The app's errors that were pending when the shim's own work began come first, oldest first;
// then the driver's.
GLenum handle_glGetError(pfn_glGetError real) {
  ContextState* c = current_context();
  if (c && !c->app_errors.empty()) {
    const GLenum e = c->app_errors.front();
    c->app_errors.erase(c->app_errors.begin());
    return e;
  }
  return real();
}

}  // namespace glbudget
