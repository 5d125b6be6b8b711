// The app's GL errors, kept apart from those of the shim's own GL work.
//
// GL keeps one flag per error code until glGetError reads it. Where the shim does GL work of
// its own in the app's context (instrumenting and building variants when the app links), it
// must neither read away errors the app has not read yet nor leave its own for the app to
// find. So the app's pending errors are moved aside first (OwnGlWork), what the shim's work
// raises is read and judged by the shim, and the app's glGetError gets its own errors back
// before the driver's.
#pragma once
#include <string>
#include <vector>

#include "gl_types.hpp"

namespace glbudget {

struct ContextState;

// The errors pending in the current context, read until GL_NO_ERROR (at most 8 reads: a lost
// context may keep answering GL_CONTEXT_LOST), each code once.
std::vector<GLenum> drain_gl_errors();

// "GL_OUT_OF_MEMORY", or the code in hex.
std::string gl_error_name(GLenum error);

// The app's pending errors in `c` (current on this thread) moved aside for its glGetError.
void keep_app_errors(ContextState& c);

// A stretch of the shim's own GL work in `c`, current on this thread: the app's pending errors
// are kept for its glGetError; at the end, errors the work raised and nobody took are read
// and dropped.
class OwnGlWork {
 public:
  explicit OwnGlWork(ContextState& c);
  ~OwnGlWork();
  OwnGlWork(const OwnGlWork&) = delete;
  OwnGlWork& operator=(const OwnGlWork&) = delete;

 private:
  ContextState& c_;
};

}  // namespace glbudget
