#include "hook_table.hpp"

#include <dlfcn.h>
#include <cstdint>

namespace glbudget {

void* g_real[kHookCount];

static uint64_t fnv1a(const char* s) {
  uint64_t x = 0xcbf29ce484222325ull;
  for (; *s; ++s) {
    x ^= static_cast<unsigned char>(*s);
    x *= 0x100000001b3ull;
  }
  return x;
}

// Not strcmp: a sanitizer's runtime reaches here through dlsym while it starts, when its own
// strcmp interceptor has no real function to call yet.
static bool same_name(const char* a, const char* b) {
  for (; *a && *a == *b; ++a, ++b) {
  }
  return *a == *b;
}

int find_hook(const char* name) {
  if (!name) return -1;
  const uint64_t mask = static_cast<uint64_t>(kHashSlots - 1);
  for (uint64_t j = fnv1a(name) & mask;; j = (j + 1) & mask) {
    const int id = kHashTable[j];
    if (id < 0) return -1;
    if (same_name(kHookNames[id], name)) return id;
  }
}

using DlsymFn = void* (*)(void*, const char*);

void* real_dlsym(void* handle, const char* name) {
  // dlvsym is not interposed, so it reaches glibc's own dlsym. glibc >= 2.34 versions it
  // GLIBC_2.34; older glibc (and other x86-64 builds) GLIBC_2.2.5. Looked up without a
  // function-local static's guard, which ThreadSanitizer intercepts and cannot serve while
  // it starts (it calls here through dlsym then); threads racing here store the same value.
  static DlsymFn cached = nullptr;
  DlsymFn fn = __atomic_load_n(&cached, __ATOMIC_ACQUIRE);
  if (!fn) {
    fn = reinterpret_cast<DlsymFn>(dlvsym(RTLD_NEXT, "dlsym", "GLIBC_2.34"));
    if (!fn) fn = reinterpret_cast<DlsymFn>(dlvsym(RTLD_NEXT, "dlsym", "GLIBC_2.2.5"));
    __atomic_store_n(&cached, fn, __ATOMIC_RELEASE);
  }
  return fn ? fn(handle, name) : nullptr;
}

using GetProcFn = void* (*)(const char*);

// The driver's GetProcAddress: whichever window-system library the process has loaded.
// Under libglvnd both return the same context-independent dispatch entry points.
static void* driver_get_proc(const char* name) {
  static const char* const kLibs[] = {"libEGL.so.1", "libGLX.so.0", "libGL.so.1"};
  static const char* const kFns[] = {"eglGetProcAddress", "glXGetProcAddressARB", "glXGetProcAddressARB"};
  for (int i = 0; i < 3; ++i) {
    void* lib = dlopen(kLibs[i], RTLD_LAZY | RTLD_NOLOAD);
    if (!lib) continue;
    auto gpa = reinterpret_cast<GetProcFn>(real_dlsym(lib, kFns[i]));
    dlclose(lib);
    if (!gpa) continue;
    // The GetProcAddress we export is a hook: never call it for the driver's answer.
    if (reinterpret_cast<void*>(gpa) == kHookAddress[find_hook(kFns[i])]) continue;
    if (void* p = gpa(name)) return p;
  }
  return nullptr;
}

void* resolve_gl(const char* name) {
  int id = find_hook(name);
  if (id >= 0 && g_real[id]) return g_real[id];
  void* p = real_dlsym(RTLD_NEXT, name);
  if (!p && name[0] == 'g' && name[1] == 'l' && name[2] != 'X') p = driver_get_proc(name);
  if (id >= 0) note_real(id, p);
  return p;
}

void* resolve_real(int id) { return resolve_gl(kHookNames[id]); }

}  // namespace glbudget
