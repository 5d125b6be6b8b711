// Fuzz target: `#define` injection (a manifest level's `defines` set in the app's GLSL).
// Input: lines NAME=VALUE (the defines, in order) up to the first line that is exactly
// "----", then the shader's source. Without that line the whole input is the source and the
// defines are SHADING_MODEL=1 and FXAA_STEPS=2 (as in the demo's manifest).
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "glbudget/instrument/defines.hpp"

namespace instrument = glbudget::instrument;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  instrument::Defines defines;
  std::string_view source = input;
  const std::size_t separator = input.starts_with("----\n") ? 0 : input.find("\n----\n");
  if (separator == std::string_view::npos) {
    defines = {{"SHADING_MODEL", "1"}, {"FXAA_STEPS", "2"}};
  } else {
    std::string_view head = input.substr(0, separator);
    source = input.substr(separator + (separator == 0 ? 5 : 6));
    while (!head.empty()) {
      const std::size_t newline = head.find('\n');
      const std::string_view line = head.substr(0, newline);
      head = newline == std::string_view::npos ? std::string_view{} : head.substr(newline + 1);
      const std::size_t eq = line.find('=');
      defines.emplace_back(std::string(line.substr(0, eq)),
                           eq == std::string_view::npos ? std::string() : std::string(line.substr(eq + 1)));
    }
  }
  const std::string out = instrument::set_defines(std::string(source), defines);
  if (defines.empty() && out != source) std::abort();  // nothing to set: unchanged
  return 0;
}
