// An initialised EGL display that needs no window system, for the test programs that render
// into pbuffers: Mesa's surfaceless platform where the driver has it (llvmpipe, Mesa's GPU
// drivers), else the first GPU of EGL_EXT_platform_device (NVIDIA's headless path), else the
// default display.
#pragma once
#include <EGL/egl.h>

namespace testapps {

struct HeadlessDisplay {
  EGLDisplay display = EGL_NO_DISPLAY;  // EGL_NO_DISPLAY when none could be initialised
  const char* platform = "none";        // "egl-surfaceless", "egl-device" or "egl-default"
};

HeadlessDisplay open_headless_egl_display();

}  // namespace testapps
