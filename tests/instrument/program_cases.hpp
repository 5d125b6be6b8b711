// The three programs of tests/instrument/shaders that gl_instrument_test checks and
// bench/instrument times: their files, the uniforms they draw with and what they count.
#pragma once

#include "gl_program.hpp"

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace glbudget::test {

struct ProgramCase {
  const char* name;
  const char* profile;  // EglContext's: "core" or "compatibility"
  const char* vertex_file;
  const char* fragment_file;
  std::function<void(GLuint)> set_uniforms;
  double fragment_instructions;  // hand counts per invocation (see the shader files)
  double fragment_texels;
  std::vector<int> fragment_warning_lines = {};  // where the driver warns in the original
};

inline void set_int_uniform(GLuint program, const char* name, int value) {
  glProgramUniform1i(program, glGetUniformLocation(program, name), value);
}

inline const std::vector<ProgramCase>& program_cases() {
  static const std::vector<ProgramCase> cases = {
      {"loops", "core", "quad.vert", "loops.frag",
       [](GLuint p) {
         set_int_uniform(p, "image", 0);
         set_int_uniform(p, "trips", 5);
         glProgramUniform1f(p, glGetUniformLocation(p, "scale"), 0.5f);
       },
       51.5, 5.0},
      {"jumps", "core", "quad_es.vert", "jumps.frag",
       [](GLuint p) {
         set_int_uniform(p, "image", 0);
         set_int_uniform(p, "mode", 0);
       },
       34.75, 1.5},
      {"compat",
       "compatibility",
       "quad_compat.vert",
       "compat.frag",
       [](GLuint p) { set_int_uniform(p, "image", 0); },
       9.5,
       2.0,
       {101}},
  };
  return cases;
}

inline const ProgramCase& program_case(const std::string& name) {
  for (const ProgramCase& c : program_cases())
    if (name == c.name) return c;
  throw std::invalid_argument("no program case " + name);
}

}  // namespace glbudget::test
