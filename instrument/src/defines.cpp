#include "glbudget/instrument/defines.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <string_view>

#include "language_version.hpp"

namespace glbudget::instrument {

namespace {

struct Line {
  std::size_t begin = 0, end = 0;  // [begin, end) without the newline; continuations joined
  long number = 1;                 // physical line of `begin`
};

std::vector<Line> split_lines(const std::string& s) {
  std::vector<Line> lines;
  std::size_t begin = 0;
  long number = 1;
  while (begin <= s.size()) {
    std::size_t end = begin;
    long physical = 0;
    for (;;) {
      end = s.find('\n', end);
      if (end == std::string::npos) {
        end = s.size();
        break;
      }
      ++physical;
      // A backslash-newline continues the directive on the next physical line.
      std::size_t k = end;
      if (k > begin && s[k - 1] == '\r') --k;
      if (k > begin && s[k - 1] == '\\') {
        ++end;
        continue;
      }
      break;
    }
    lines.push_back({begin, end, number});
    number += physical;
    if (end >= s.size()) break;
    begin = end + 1;
  }
  return lines;
}

std::string_view skip_space(std::string_view v) {
  while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
  return v;
}

// The directive name of a line (`define` for `  #  define X 1`), or empty.
std::string_view directive(std::string_view line, std::string_view* rest) {
  line = skip_space(line);
  if (line.empty() || line.front() != '#') return {};
  line = skip_space(line.substr(1));
  std::size_t n = 0;
  while (n < line.size() && std::isalpha(static_cast<unsigned char>(line[n]))) ++n;
  if (rest) *rest = line.substr(n);
  return line.substr(0, n);
}

bool is_identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// True when the line is `#define NAME` followed by a space, the end, or a comment (an
// object-like macro; `NAME(` is a function-like one, which a value cannot replace).
bool defines_name(std::string_view line, const std::string& name) {
  std::string_view rest;
  if (directive(line, &rest) != "define" || rest.empty() || (rest.front() != ' ' && rest.front() != '\t')) return false;
  rest = skip_space(rest);
  if (rest.substr(0, name.size()) != name) return false;
  return rest.size() == name.size() || (!is_identifier_char(rest[name.size()]) && rest[name.size()] != '(');
}

// 110 for a shader without #version; `es` for `#version 300 es` and ES 1.00.
LanguageVersion language_of(const std::string& s, const std::vector<Line>& lines) {
  for (const Line& l : lines) {
    std::string_view rest;
    if (directive(std::string_view(s).substr(l.begin, l.end - l.begin), &rest) == "version")
      return version_directive_language(rest);
  }
  return {};
}

// Offset where added directives go: after #version and the #extension lines (and blank or
// comment lines between them) that open the shader.
std::size_t insertion_point(const std::string& s, const std::vector<Line>& lines, long* next_line) {
  std::size_t point = 0;
  *next_line = 1;
  bool in_block_comment = false;
  for (const Line& l : lines) {
    std::string_view text = skip_space(std::string_view(s).substr(l.begin, l.end - l.begin));
    if (in_block_comment) {
      if (text.find("*/") != std::string_view::npos) in_block_comment = false;
      continue;
    }
    if (text.empty() || text.substr(0, 2) == "//") continue;
    if (text.substr(0, 2) == "/*") {
      in_block_comment = text.find("*/", 2) == std::string_view::npos;
      continue;
    }
    const std::string_view name = directive(text, nullptr);
    if (name != "version" && name != "extension") break;
    point = l.end < s.size() ? l.end + 1 : s.size();
    *next_line = l.number + 1 + static_cast<long>(std::count(s.begin() + l.begin, s.begin() + l.end, '\n'));
  }
  return point;
}

}  // namespace

std::string set_defines(const std::string& source, const Defines& defines) {
  if (defines.empty()) return source;
  const std::vector<Line> lines = split_lines(source);
  std::string out;
  std::vector<bool> found(defines.size(), false);
  // Redefine in place, line by line.
  std::string rewritten;
  rewritten.reserve(source.size() + 64);
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const Line& l = lines[i];
    std::string_view text(source.data() + l.begin, l.end - l.begin);
    bool replaced = false;
    for (std::size_t d = 0; d < defines.size() && !replaced; ++d) {
      if (!defines_name(text, defines[d].first)) continue;
      found[d] = replaced = true;
      // Keep the physical line count of a continued directive.
      const auto newlines = std::count(text.begin(), text.end(), '\n');
      rewritten += "#define " + defines[d].first + " " + defines[d].second;
      rewritten.append(static_cast<std::size_t>(newlines), '\n');
    }
    if (!replaced) rewritten.append(text);
    if (l.end < source.size()) rewritten += '\n';
  }
  std::string added;
  for (std::size_t d = 0; d < defines.size(); ++d)
    if (!found[d]) added += "#define " + defines[d].first + " " + defines[d].second + "\n";
  if (added.empty()) return rewritten;

  const std::vector<Line> new_lines = split_lines(rewritten);
  long next_line = 1;
  std::size_t point = insertion_point(rewritten, new_lines, &next_line);
  const LanguageVersion language = language_of(rewritten, new_lines);
  const long named = line_names_next_line(language) ? next_line : next_line - 1;
  std::string prefix = rewritten.substr(0, point);
  if (!prefix.empty() && prefix.back() != '\n') prefix += '\n';
  return prefix + added + "#line " + std::to_string(named) + "\n" + rewritten.substr(point);
}

}  // namespace glbudget::instrument
