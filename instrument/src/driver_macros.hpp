// glslang preprocesses the shader for the instrumenter, and it predefines the extension
// macros (GL_ARB_...) of the extensions *it* knows, not those of the driver the app runs
// on. A shader that tests `#ifdef GL_ARB_foo` could then take another branch instrumented
// than plain. GLSL forbids (un)defining GL_ names, so the conditionals are rewritten to test
// GLBUDGET_DRIVER_GL_foo instead, defined exactly for the driver's extensions.
#pragma once

#include <string>
#include <vector>

namespace glbudget::instrument {

struct DriverMacroSource {
  std::string source;    // conditionals on extension macros renamed; lines unchanged
  std::string preamble;  // #define GLBUDGET_DRIVER_<name> 1 for every driver extension tested
};

DriverMacroSource with_driver_extension_macros(const std::string& source,
                                               const std::vector<std::string>& driver_extensions);

}  // namespace glbudget::instrument
