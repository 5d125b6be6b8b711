// Reading and writing one uniform of any GL type on any program: copying the app's values into
// a variant after it links, and holding a manifest level's values.
#pragma once
#include <vector>

#include "gl_types.hpp"

namespace glbudget {

// Copies the value of one uniform (one array element) from `from` to `to`. False for types
// that cannot be set (atomic counters) or when the driver lacks a needed entry point.
bool copy_uniform(GLuint from, GLint from_location, GLuint to, GLint to_location, GLenum type);

// Writes `values` (flattened, column-major for matrices) to consecutive elements starting at
// `location`: as many whole elements as `values` holds, at most `max_elements`. False when the
// count does not fill a whole element of `type`.
bool set_uniform(GLuint program, GLint location, GLenum type, GLint max_elements, const std::vector<double>& values);

// Components per element of a uniform type (16 for a mat4); 0 for types that cannot be set.
int uniform_components(GLenum type);

}  // namespace glbudget
