#include "driver_macros.hpp"

#include <algorithm>
#include <cctype>
#include <set>
#include <string_view>

namespace glbudget::instrument {

namespace {

// GL_ macros that describe the language, not an extension: glslang gets them right.
bool is_language_macro(std::string_view name) {
  return name == "GL_ES" || name == "GL_core_profile" || name == "GL_compatibility_profile" ||
         name == "GL_FRAGMENT_PRECISION_HIGH" || name == "GL_SPIRV";
}

bool identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

bool is_conditional(std::string_view line) {
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string_view::npos || line[i] != '#') return false;
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string_view::npos) return false;
  const std::string_view directive = line.substr(i);
  for (std::string_view d : {"ifdef", "ifndef", "if", "elif"}) {
    if (directive.substr(0, d.size()) == d && (directive.size() == d.size() || !identifier_char(directive[d.size()])))
      return true;
  }
  return false;
}

}  // namespace

DriverMacroSource with_driver_extension_macros(const std::string& source,
                                               const std::vector<std::string>& driver_extensions) {
  const std::set<std::string, std::less<>> supported(driver_extensions.begin(), driver_extensions.end());
  std::set<std::string> tested;
  DriverMacroSource result;
  std::size_t start = 0;
  while (start < source.size()) {
    std::size_t end = source.find('\n', start);
    if (end == std::string::npos) end = source.size();
    const std::string_view line(source.data() + start, end - start);
    if (!is_conditional(line)) {
      result.source.append(line);
    } else {
      for (std::size_t i = 0; i < line.size();) {
        const bool word_start = i == 0 || !identifier_char(line[i - 1]);
        if (word_start && line.substr(i, 3) == "GL_") {
          std::size_t j = i;
          while (j < line.size() && identifier_char(line[j])) ++j;
          const std::string_view name = line.substr(i, j - i);
          if (!is_language_macro(name)) {
            result.source += "GLBUDGET_DRIVER_";
            tested.insert(std::string(name));
          }
          result.source.append(name);
          i = j;
        } else {
          result.source += line[i++];
        }
      }
    }
    if (end < source.size()) result.source += '\n';
    start = end + 1;
  }
  for (const std::string& name : tested)
    if (supported.count(name)) result.preamble += "#define GLBUDGET_DRIVER_" + name + " 1\n";
  return result;
}

}  // namespace glbudget::instrument
