// Fuzz target: GLBUDGET_FORCE ("1,0,2": one level per pass), checked against a manifest.
// Input: byte 0: the number of passes (mod 8); bytes 1..passes: the level count of each
// (mod 16, at least 1); the rest: the value. A value that parses names a level of each pass.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "glbudget/manifest/manifest.hpp"

namespace manifest = glbudget::manifest;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return -1;
  const std::size_t passes = data[0] % 8;
  if (size < 1 + passes) return -1;
  manifest::Manifest m;
  for (std::size_t i = 0; i < passes; ++i) {
    manifest::Pass pass;
    pass.name = "pass" + std::to_string(i);
    pass.levels.resize(data[1 + i] % 16 + 1);
    m.passes.push_back(std::move(pass));
  }
  const std::string text(reinterpret_cast<const char*>(data) + 1 + passes, size - 1 - passes);
  std::string error;
  const std::optional<std::vector<int>> levels = manifest::parse_force(text, m, &error);
  if (!levels) {
    if (error.empty()) std::abort();  // a rejection says why
    return 0;
  }
  if (levels->size() != m.passes.size()) std::abort();
  for (std::size_t i = 0; i < levels->size(); ++i) {
    if ((*levels)[i] < 0 || static_cast<std::size_t>((*levels)[i]) >= m.passes[i].levels.size()) std::abort();
  }
  return 0;
}
