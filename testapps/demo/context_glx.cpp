#include <GL/glx.h>
#include <X11/Xlib.h>

#include <stdexcept>
#include <string>

#include "context.hpp"

namespace demo {
namespace {

using CreateContextAttribs = GLXContext (*)(Display*, GLXFBConfig, GLXContext, Bool, const int*);

class GlxContext : public GlContext {
 public:
  GlxContext(int width, int height) {
    display_ = XOpenDisplay(nullptr);
    if (!display_) throw std::runtime_error("cannot open X display (is DISPLAY set?)");
    try {
      create(width, height);
    } catch (...) {
      release();  // the destructor does not run when the constructor throws
      throw;
    }
  }
  ~GlxContext() override { release(); }

  void swap_buffers() override { glXSwapBuffers(display_, window_); }
  const char* kind() const override { return "glx"; }

 private:
  void create(int width, int height) {
    const int attributes[] = {GLX_X_RENDERABLE,
                              True,
                              GLX_DRAWABLE_TYPE,
                              GLX_WINDOW_BIT,
                              GLX_RENDER_TYPE,
                              GLX_RGBA_BIT,
                              GLX_RED_SIZE,
                              8,
                              GLX_GREEN_SIZE,
                              8,
                              GLX_BLUE_SIZE,
                              8,
                              GLX_ALPHA_SIZE,
                              8,
                              GLX_DOUBLEBUFFER,
                              True,
                              None};
    int count = 0;
    GLXFBConfig* configs = glXChooseFBConfig(display_, DefaultScreen(display_), attributes, &count);
    if (!configs || count == 0) throw std::runtime_error("glXChooseFBConfig found no RGBA8 double-buffered config");
    const GLXFBConfig config = configs[0];
    XFree(configs);
    XVisualInfo* visual = glXGetVisualFromFBConfig(display_, config);
    if (!visual) throw std::runtime_error("glXGetVisualFromFBConfig failed");
    const Window root = RootWindow(display_, visual->screen);
    XSetWindowAttributes window_attributes{};
    window_attributes.colormap = colormap_ = XCreateColormap(display_, root, visual->visual, AllocNone);
    window_attributes.event_mask = StructureNotifyMask;
    window_ = XCreateWindow(display_, root, 0, 0, static_cast<unsigned>(width), static_cast<unsigned>(height), 0,
                            visual->depth, InputOutput, visual->visual, CWColormap | CWEventMask, &window_attributes);
    XFree(visual);
    XStoreName(display_, window_, "demo");
    XMapWindow(display_, window_);
    XEvent event;
    do XNextEvent(display_, &event);
    while (event.type != MapNotify);

    const auto create_context = reinterpret_cast<CreateContextAttribs>(
        glXGetProcAddressARB(reinterpret_cast<const GLubyte*>("glXCreateContextAttribsARB")));
    if (!create_context) throw std::runtime_error("GLX_ARB_create_context is missing");
    const int context_attributes[] = {
        GLX_CONTEXT_MAJOR_VERSION_ARB,    3,   GLX_CONTEXT_MINOR_VERSION_ARB, 3, GLX_CONTEXT_PROFILE_MASK_ARB,
        GLX_CONTEXT_CORE_PROFILE_BIT_ARB, None};
    context_ = create_context(display_, config, nullptr, True, context_attributes);
    if (!context_) throw std::runtime_error("glXCreateContextAttribsARB (OpenGL 3.3 core) failed");
    if (!glXMakeCurrent(display_, window_, context_)) throw std::runtime_error("glXMakeCurrent failed");
  }

  void release() {
    if (!display_) return;
    glXMakeCurrent(display_, None, nullptr);
    if (context_) glXDestroyContext(display_, context_);
    if (window_) XDestroyWindow(display_, window_);
    if (colormap_) XFreeColormap(display_, colormap_);
    XCloseDisplay(display_);
    display_ = nullptr;
  }

  Display* display_ = nullptr;
  Window window_ = 0;
  Colormap colormap_ = 0;
  GLXContext context_ = nullptr;
};

}  // namespace

std::unique_ptr<GlContext> create_glx_context(int width, int height) {
  auto context = std::make_unique<GlxContext>(width, height);
  load_gl_functions(false);
  return context;
}

}  // namespace demo
