// Where the app's glUniform* and glProgramUniform* calls go when variants are in play (the
// generated wrappers call these). Null: no variant concerns the call, so it goes straight to
// the driver; that is every call of an app without a manifest.
#pragma once
#include "variants.hpp"

namespace glbudget {

// For glUniform*: the program the app has bound (by glUseProgram).
const UniformTargets* bound_uniform_targets(GLint location);
// For glProgramUniform*.
const UniformTargets* program_uniform_targets(GLuint program, GLint location);

}  // namespace glbudget
