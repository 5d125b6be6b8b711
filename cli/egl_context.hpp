// An OpenGL context with no window and no display server, for `glbudget ssim --gpu` and the
// GPU SSIM test: EGL's surfaceless platform (EGL_MESA_platform_surfaceless; llvmpipe needs no
// GPU), else its device platform (EGL_EXT_platform_device: NVIDIA's), current on the calling
// thread.
#pragma once
#include <memory>
#include <string>

namespace glbudget::cli {

enum class GlApi { kDesktop, kEs };

class HeadlessGlContext {
 public:
  // kDesktop: OpenGL 4.3 or later, core profile; kEs: OpenGL ES 3.1 or later. Made current.
  // Null, and why in *why_not, if EGL cannot give one.
  static std::unique_ptr<HeadlessGlContext> open(GlApi api, std::string* why_not);
  ~HeadlessGlContext();
  HeadlessGlContext(const HeadlessGlContext&) = delete;
  HeadlessGlContext& operator=(const HeadlessGlContext&) = delete;

  // Current again on this thread, after another context was.
  bool make_current();
  GlApi api() const { return api_; }
  // eglGetProcAddress, for core and extension entry points alike (EGL 1.5): a GlProcLoader.
  static void* proc_address(const char* name);

 private:
  HeadlessGlContext(void* display, void* context, GlApi api) : display_(display), context_(context), api_(api) {}
  void* display_;  // EGLDisplay
  void* context_;  // EGLContext
  GlApi api_;
};

}  // namespace glbudget::cli
