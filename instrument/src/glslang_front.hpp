// glslang as the instrumenter uses it: preprocessing, and parsing preprocessed text for the
// operation census. The only file that includes glslang's public API.
#pragma once

#include "ast_census.hpp"
#include "glbudget/instrument/instrument.hpp"
#include "language_version.hpp"

#include <string>
#include <vector>

namespace glbudget::instrument {

struct Preprocessed {
  bool ok = false;
  std::string text;   // macros expanded, conditionals resolved, #line kept
  std::string error;  // glslang's first error line
};

// Preprocesses the concatenated sources as the driver would; `preamble` is seen first.
Preprocessed preprocess(const std::string& source, Stage stage, const std::string& preamble = {});

struct Parsed {
  bool ok = false;
  std::string error;
  LanguageVersion language;
  std::vector<CountedNode> nodes;  // positions are physical lines of `text`
};

// Parses preprocessed text. Its #line directives must have been blanked so that glslang's
// positions are physical lines.
Parsed parse_for_census(const std::string& text, Stage stage);

}  // namespace glbudget::instrument
