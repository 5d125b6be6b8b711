// GL types and calling conventions for the generated dispatch layer. Prototypes come from the
// registry (gen/gen_hooks.py), so only the type definitions are taken from the system headers.
#pragma once
#include <GL/gl.h>
#include <GL/glext.h>
#ifndef APIENTRY
#define APIENTRY
#endif
#ifndef APIENTRYP
#define APIENTRYP APIENTRY*
#endif
