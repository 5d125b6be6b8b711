// What glXGetProcAddress / eglGetProcAddress / dlsym hand back for a name the driver knows.
#pragma once

namespace glbudget {

// `real` is the driver's answer. For a hooked name we remember it and answer with our hook;
// otherwise (or when the driver has no such function) the driver's answer goes back untouched.
void* hook_for_proc(const char* name, void* real);

}  // namespace glbudget
