// The GLSL language a shader is written in, as its #version directive says.
#pragma once

#include <cctype>
#include <cstdlib>
#include <string>
#include <string_view>

namespace glbudget::instrument {

struct LanguageVersion {
  int version = 110;
  bool es = false;
  bool compatibility = false;  // desktop compatibility profile (or no profile below 150)
};

// The language of `#version 300 es`, `#version 330 core` from the directive's text after its
// name (" 300 es"): its first number, ES for an `es` profile or version 100. A directive with
// no number keeps 110, GLSL's version without one.
inline LanguageVersion version_directive_language(std::string_view rest) {
  LanguageVersion language;
  const std::size_t digits = rest.find_first_of("0123456789");
  if (digits != std::string_view::npos) language.version = std::atoi(std::string(rest.substr(digits)).c_str());
  const std::size_t profile = rest.find_first_not_of("0123456789 \t", digits == std::string_view::npos ? 0 : digits);
  language.es = (profile != std::string_view::npos && rest.substr(profile, 2) == "es" &&
                 (profile + 2 == rest.size() || !std::isalnum(static_cast<unsigned char>(rest[profile + 2])))) ||
                language.version == 100;
  return language;
}

// GLSL changed #line: from desktop 3.30 and in every ES version the line after `#line L`
// is L; before, it is L + 1.
inline bool line_names_next_line(const LanguageVersion& language) { return language.es || language.version >= 330; }

}  // namespace glbudget::instrument
