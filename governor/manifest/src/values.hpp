#pragma once
// Private to the parser: the manifest's value types, checked and converted. Each returns
// nullopt for a value it cannot take; the caller reports where.
#include "toml.hpp"

#include <optional>
#include <string>
#include <string_view>

#include "glbudget/manifest/manifest.hpp"

namespace glbudget::manifest::detail {

// An integer or a float.
std::optional<double> number(const toml::node& node);

// A define's value as GLSL text: integers as written, floats with a decimal point (1.0, 0.25,
// 1.0e-05), true / false, strings verbatim (one line). Not: inf, nan, tables, arrays, dates.
std::optional<std::string> define_text(const toml::node& node);

// A number, a bool (1 / 0) or an array of them, nested arrays flattened; never empty.
std::optional<UniformValue> uniform_value(const toml::node& node);

Target make_target(Target::Kind kind, std::string name = {}, uint32_t id = 0);
// "self", "default", "window-sized", "pass:NAME", "texture:N", "framebuffer:N" with 1 <= N < 2^32.
std::optional<Target> parse_target(std::string_view text);
std::string target_text(const Target& target);

// [A-Za-z_][A-Za-z0-9_]*: a GLSL macro name.
bool is_identifier(std::string_view name);

}  // namespace glbudget::manifest::detail
