#include "window_size.hpp"

#include <EGL/egl.h>
#include <GL/glx.h>
#include <dlfcn.h>

#include "hook_table.hpp"

namespace glbudget {

namespace {
// A window-system function we never hook: the next definition, else the library's own.
void* winsys_function(const char* library, const char* name) {
  if (void* p = real_dlsym(RTLD_NEXT, name)) return p;
  void* lib = dlopen(library, RTLD_LAZY | RTLD_NOLOAD);
  if (!lib) return nullptr;
  void* p = real_dlsym(lib, name);
  dlclose(lib);
  return p;
}
}  // namespace

bool current_window_size(bool egl, int* width, int* height) {
  if (egl) {
    static auto display =
        reinterpret_cast<decltype(&eglGetCurrentDisplay)>(winsys_function("libEGL.so.1", "eglGetCurrentDisplay"));
    static auto surface =
        reinterpret_cast<decltype(&eglGetCurrentSurface)>(winsys_function("libEGL.so.1", "eglGetCurrentSurface"));
    static auto query = reinterpret_cast<decltype(&eglQuerySurface)>(winsys_function("libEGL.so.1", "eglQuerySurface"));
    if (!display || !surface || !query) return false;
    EGLDisplay d = display();
    EGLSurface s = surface(EGL_DRAW);
    EGLint w = 0, h = 0;
    if (d == EGL_NO_DISPLAY || s == EGL_NO_SURFACE || !query(d, s, EGL_WIDTH, &w) || !query(d, s, EGL_HEIGHT, &h))
      return false;
    *width = w;
    *height = h;
    return w > 0 && h > 0;
  }
  static auto display =
      reinterpret_cast<decltype(&glXGetCurrentDisplay)>(winsys_function("libGLX.so.0", "glXGetCurrentDisplay"));
  static auto drawable =
      reinterpret_cast<decltype(&glXGetCurrentDrawable)>(winsys_function("libGLX.so.0", "glXGetCurrentDrawable"));
  static auto query = reinterpret_cast<decltype(&glXQueryDrawable)>(winsys_function("libGLX.so.0", "glXQueryDrawable"));
  if (!display || !drawable || !query) return false;
  Display* d = display();
  GLXDrawable draw = drawable();
  if (!d || !draw) return false;
  unsigned int w = 0, h = 0;
  query(d, draw, GLX_WIDTH, &w);
  query(d, draw, GLX_HEIGHT, &h);
  *width = static_cast<int>(w);
  *height = static_cast<int>(h);
  return w > 0 && h > 0;
}

}  // namespace glbudget
