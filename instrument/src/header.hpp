// The declarations glbudget adds to a shader: the counter block, the per-invocation
// counters and the flush function, placed after the app's #version/#extension directives and
// followed by a #line directive so that the app's lines keep their numbers.
#pragma once

#include "glslang_front.hpp"
#include "rewrite.hpp"
#include "syntax.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace glbudget::instrument {

struct HeaderPlan {
  std::vector<Insertion> insertions;
  bool binding_in_source = false;
};

// Where added lines go in preprocessed text: extension directives after #version, declarations
// after the last #extension (both before the first function). A directive that ends the text
// gets its newline. Throws std::runtime_error when an #extension follows the first function.
struct HeaderPoints {
  const syntax::Directive* version = nullptr;
  std::size_t extension = 0;
  std::size_t declaration = 0;
};
HeaderPoints header_points(std::string& text, const syntax::Unit& unit);
// The #line directive after lines inserted at `offset`, so that the app's lines keep their numbers.
std::string line_fixup(std::string_view text, const syntax::Unit& unit, std::size_t offset,
                       const LanguageVersion& language);

// May edit `text` in place (GLSL ES 3.00 is raised to 3.10, the first with storage buffers).
// Throws std::runtime_error when the language has no storage buffers.
HeaderPlan plan_header(std::string& text, const syntax::Unit& unit, const LanguageVersion& language, Stage stage,
                       int binding);

}  // namespace glbudget::instrument
