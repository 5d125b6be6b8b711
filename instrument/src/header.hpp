// The declarations glbudget adds to a shader: the counter block, the per-invocation
// counters and the flush function, placed after the app's #version/#extension directives and
// followed by a #line directive so that the app's lines keep their numbers.
#pragma once

#include "glslang_front.hpp"
#include "rewrite.hpp"
#include "syntax.hpp"

#include <string>
#include <vector>

namespace glbudget::instrument {

struct HeaderPlan {
  std::vector<Insertion> insertions;
  bool binding_in_source = false;
};

// May edit `text` in place (GLSL ES 3.00 is raised to 3.10, the first with storage buffers).
// Throws std::runtime_error when the language has no storage buffers.
HeaderPlan plan_header(std::string& text, const syntax::Unit& unit, const LanguageVersion& language, Stage stage,
                       int binding);

}  // namespace glbudget::instrument
