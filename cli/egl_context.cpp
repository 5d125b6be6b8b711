#include "egl_context.hpp"

#define EGL_NO_X11  // the surfaceless platform needs no Xlib, nor its macros
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>

namespace glbudget::cli {

namespace {

bool has_extension(const char* list, const char* name) {
  if (!list) return false;
  const std::size_t length = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += length)
    if ((p == list || p[-1] == ' ') && (p[length] == ' ' || p[length] == '\0')) return true;
  return false;
}

std::string egl_error(const char* what) {
  char code[16];
  std::snprintf(code, sizeof code, "0x%04x", static_cast<unsigned>(eglGetError()));
  return std::string(what) + " failed (EGL error " + code + ")";
}

bool fail(std::string* why_not, std::string text) {
  if (why_not) *why_not = std::move(text);
  return false;
}

EGLDisplay initialised(EGLDisplay display, const char* how, std::string* why_not) {
  if (display == EGL_NO_DISPLAY) {
    fail(why_not, egl_error(how));
    return EGL_NO_DISPLAY;
  }
  if (!eglInitialize(display, nullptr, nullptr)) {
    fail(why_not, egl_error("eglInitialize"));
    return EGL_NO_DISPLAY;
  }
  return display;
}

// A display with no window system: Mesa's surfaceless platform (llvmpipe, Mesa's GPU drivers),
// else the first GPU of EGL_EXT_platform_device (NVIDIA's headless path).
EGLDisplay headless_display(std::string* why_not) {
  const char* client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (has_extension(client, "EGL_MESA_platform_surfaceless")) {
    EGLDisplay display = initialised(eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr),
                                     "eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA)", why_not);
    if (display != EGL_NO_DISPLAY) return display;
  }
  auto query_devices = reinterpret_cast<PFNEGLQUERYDEVICESEXTPROC>(eglGetProcAddress("eglQueryDevicesEXT"));
  if (!has_extension(client, "EGL_EXT_platform_device") || query_devices == nullptr) {
    fail(why_not,
         "EGL has neither a surfaceless platform (EGL_MESA_platform_surfaceless) nor a device one "
         "(EGL_EXT_platform_device)");
    return EGL_NO_DISPLAY;
  }
  EGLDeviceEXT devices[16];
  EGLint count = 0;
  if (!query_devices(16, devices, &count) || count == 0) {
    fail(why_not, egl_error("eglQueryDevicesEXT"));
    return EGL_NO_DISPLAY;
  }
  for (EGLint i = 0; i < count; ++i) {
    EGLDisplay display = initialised(eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT, devices[i], nullptr),
                                     "eglGetPlatformDisplay(EGL_PLATFORM_DEVICE_EXT)", why_not);
    if (display != EGL_NO_DISPLAY) return display;
  }
  return EGL_NO_DISPLAY;
}

// EGL_NO_CONFIG_KHR where the display allows it (nothing is drawn to a surface), else any
// config that renders with the API.
bool pick_config(EGLDisplay display, GlApi api, EGLConfig& config, std::string* why_not) {
  if (has_extension(eglQueryString(display, EGL_EXTENSIONS), "EGL_KHR_no_config_context")) {
    config = EGL_NO_CONFIG_KHR;
    return true;
  }
  const EGLint attributes[] = {EGL_RENDERABLE_TYPE, api == GlApi::kDesktop ? EGL_OPENGL_BIT : EGL_OPENGL_ES3_BIT,
                               EGL_NONE};
  EGLint count = 0;
  if (!eglChooseConfig(display, attributes, &config, 1, &count) || count == 0)
    return fail(why_not, egl_error("eglChooseConfig"));
  return true;
}

}  // namespace

std::unique_ptr<HeadlessGlContext> HeadlessGlContext::open(GlApi api, std::string* why_not) {
  // The display is not terminated with the context: EGL shares one per platform in a process,
  // and another context (a test's second one) may still be on it.
  EGLDisplay display = headless_display(why_not);
  if (display == EGL_NO_DISPLAY) return nullptr;
  const bool desktop = api == GlApi::kDesktop;
  const char* name = desktop ? "OpenGL 4.3 core" : "OpenGL ES 3.1";
  if (!eglBindAPI(desktop ? EGL_OPENGL_API : EGL_OPENGL_ES_API)) {
    fail(why_not, egl_error(desktop ? "eglBindAPI(EGL_OPENGL_API)" : "eglBindAPI(EGL_OPENGL_ES_API)"));
    return nullptr;
  }
  EGLConfig config = nullptr;
  if (!pick_config(display, api, config, why_not)) return nullptr;
  const EGLint desktop_attributes[] = {
      EGL_CONTEXT_MAJOR_VERSION,           4,       EGL_CONTEXT_MINOR_VERSION, 3, EGL_CONTEXT_OPENGL_PROFILE_MASK,
      EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLint es_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 1, EGL_NONE};
  EGLContext context = eglCreateContext(display, config, EGL_NO_CONTEXT, desktop ? desktop_attributes : es_attributes);
  if (context == EGL_NO_CONTEXT) {
    fail(why_not, egl_error((std::string("eglCreateContext (") + name + ")").c_str()));
    return nullptr;
  }
  std::unique_ptr<HeadlessGlContext> result(new HeadlessGlContext(display, context, api));
  if (!result->make_current()) {
    fail(why_not, egl_error("eglMakeCurrent without a surface"));
    return nullptr;
  }
  return result;
}

HeadlessGlContext::~HeadlessGlContext() {
  eglBindAPI(api_ == GlApi::kDesktop ? EGL_OPENGL_API : EGL_OPENGL_ES_API);
  if (eglGetCurrentContext() == context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(display_, context_);
}

bool HeadlessGlContext::make_current() {
  // The thread's bound API decides what eglGetCurrentContext answers: ours, from now on.
  eglBindAPI(api_ == GlApi::kDesktop ? EGL_OPENGL_API : EGL_OPENGL_ES_API);
  return eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_) == EGL_TRUE;
}

void* HeadlessGlContext::proc_address(const char* name) { return reinterpret_cast<void*>(eglGetProcAddress(name)); }

}  // namespace glbudget::cli
