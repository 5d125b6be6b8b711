// The size of the surface the current context draws to, as the window system reports it
// (eglQuerySurface, glXQueryDrawable): what the default framebuffer's stand-in follows.
#pragma once

namespace glbudget {

bool current_window_size(bool egl, int* width, int* height);

}  // namespace glbudget
