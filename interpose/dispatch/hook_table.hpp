// The table of real (driver) entry points behind every hook, and the name -> hook lookup
// shared by dlsym, glXGetProcAddress and eglGetProcAddress interception.
#pragma once
#include "hooks_generated.hpp"

// What the shim exports (the version script exports these names and nothing else).
#define GLBUDGET_EXPORT extern "C" __attribute__((visibility("default")))

namespace glbudget {

extern const char* const kHookNames[kHookCount];
extern void* const kHookAddress[kHookCount];
extern const int kHashSlots;
extern const short kHashTable[];

// Real entry points, filled lazily. A relaxed atomic would be pedantically right; plain
// pointer-sized loads and stores are atomic on every platform we run on, and every writer
// stores the same driver address.
extern void* g_real[kHookCount];

// Hook id for an entry-point name, or -1. Hashed (FNV-1a, build-time table), one strcmp.
int find_hook(const char* name);

// Resolves a real entry point the app never handed us: the next definition after us in the
// global scope (the app linked libGL/libOpenGL/libEGL), else the driver's GetProcAddress.
void* resolve_real(int id);

inline void* real_entry(int id) {
  void* p = g_real[id];
  return p ? p : resolve_real(id);
}

// The same, typed: real_function<decltype(&eglSwapBuffers)>(kHook_eglSwapBuffers).
template <typename F>
F real_function(int id) {
  return reinterpret_cast<F>(real_entry(id));
}

// Records a real entry point obtained from the driver (GetProcAddress or dlsym on a GL library).
inline void note_real(int id, void* p) {
  if (p && !g_real[id]) g_real[id] = p;
}

// glibc's dlsym, bypassing our own exported dlsym.
void* real_dlsym(void* handle, const char* name);

// Any GL/GLX/EGL function by name (for the shim's own calls): RTLD_NEXT, then GetProcAddress.
void* resolve_gl(const char* name);

}  // namespace glbudget
