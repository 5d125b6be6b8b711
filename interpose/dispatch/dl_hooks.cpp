// dlsym interception, for apps (and toolkits: GLFW, SDL, epoxy, glad) that dlopen the GL
// library and look entry points up by handle, where symbol interposition cannot reach.
// Also _exit/_Exit, which skip atexit handlers but must still flush the frame log.
#include <dlfcn.h>
#include <link.h>
#include <sys/syscall.h>
#include <unistd.h>

#include "frame_output.hpp"
#include "hook_table.hpp"
#include "proc_address.hpp"

using namespace glbudget;

namespace glbudget {

void* hook_for_proc(const char* name, void* real) {
  if (!real) return nullptr;
  int id = find_hook(name);
  if (id < 0) return real;
  if (real == kHookAddress[id]) return real;
  note_real(id, real);
  return kHookAddress[id];
}

}  // namespace glbudget

namespace {
link_map* object_of(const void* addr) {
  Dl_info info;
  link_map* lm = nullptr;
  if (!dladdr1(addr, &info, reinterpret_cast<void**>(&lm), RTLD_DL_LINKMAP)) return nullptr;
  return lm;
}

// The definition of `name` in object `l` itself (not its dependencies), or null.
void* symbol_in(link_map* l, const char* name) {
  if (!l->l_name || !l->l_name[0]) return nullptr;
  void* h = dlopen(l->l_name, RTLD_LAZY | RTLD_NOLOAD);
  if (!h) return nullptr;
  void* p = real_dlsym(h, name);
  dlclose(h);
  return p && object_of(p) == l ? p : nullptr;
}

// Our own definitions of what is not GL (the process-exit hooks below): what an object just
// before us (a sanitizer runtime, another interposer) must find as the next definition.
void* own_definition(const char* name);

// dlsym(RTLD_NEXT) must search after the *caller's* object; called from here, glibc would
// search after ours. So walk the link map from the caller on, as the dynamic linker does.
void* next_after(const void* caller, const char* name) {
  link_map* me = object_of(reinterpret_cast<const void*>(&next_after));
  link_map* from = object_of(caller);
  if (!from || !me) return nullptr;
  int id = find_hook(name);
  if (from->l_next == me) {
    // The caller comes just before us (a sanitizer runtime preloaded ahead of us, resolving
    // its interceptors' real functions while it starts): what follows it is us, then what
    // follows us, which glibc searches itself when asked from here. No dlopen either, which
    // such a runtime intercepts and cannot serve before it has started.
    if (void* p = own_definition(name)) return p;
    if (void* p = real_dlsym(RTLD_NEXT, name)) return id < 0 ? p : hook_for_proc(name, p);
    if (id < 0) return nullptr;
    void* p = real_entry(id);
    return p ? kHookAddress[id] : nullptr;
  }
  for (link_map* l = from->l_next; l; l = l->l_next) {
    if (l == me) {
      if (void* p = own_definition(name)) return p;
      if (id < 0) continue;  // we define nothing else for others to see
      // The next definition after ours is the real one behind our hook.
      for (link_map* r = me->l_next; r; r = r->l_next)
        if (void* p = symbol_in(r, name)) return hook_for_proc(name, p);
      void* p = real_entry(id);
      return p ? kHookAddress[id] : nullptr;
    }
    if (void* p = symbol_in(l, name)) return p;
  }
  return nullptr;
}
}  // namespace

GLBUDGET_EXPORT void* dlsym(void* __restrict handle, const char* __restrict name) {
  if (handle == RTLD_NEXT) return next_after(__builtin_return_address(0), name);
  return hook_for_proc(name, real_dlsym(handle, name));
}

[[noreturn]] static void real_exit_call(const char* which, int status) {
  using ExitFn = void (*)(int);
  auto fn = reinterpret_cast<ExitFn>(real_dlsym(RTLD_NEXT, which));
  if (fn) fn(status);
  syscall(SYS_exit_group, status);
  __builtin_unreachable();
}

GLBUDGET_EXPORT void _exit(int status) {
  final_flush();
  real_exit_call("_exit", status);
}

GLBUDGET_EXPORT void _Exit(int status) {
  final_flush();
  real_exit_call("_Exit", status);
}

// Hidden aliases: their addresses are ours, where `&_exit` would be whichever definition comes
// first in the process (an interceptor preloaded ahead of us).
extern "C" void glbudget_own_exit(int) __attribute__((copy(_exit), visibility("hidden"), alias("_exit")));
extern "C" void glbudget_own_Exit(int) __attribute__((copy(_Exit), visibility("hidden"), alias("_Exit")));

namespace {
// No strcmp: a sanitizer runtime intercepts it and asks us while it starts.
bool same_name(const char* a, const char* b) {
  while (*a && *a == *b) ++a, ++b;
  return *a == *b;
}

void* own_definition(const char* name) {
  if (same_name(name, "_exit")) return reinterpret_cast<void*>(&glbudget_own_exit);
  if (same_name(name, "_Exit")) return reinterpret_cast<void*>(&glbudget_own_Exit);
  return nullptr;
}
}  // namespace
