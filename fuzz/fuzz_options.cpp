// Fuzz target: the shim's GLBUDGET_* environment (interpose/state/options.cpp, GL-free).
// Input: the environment, one NAME=VALUE per line (as in `env`); lines without a GLBUDGET_
// prefix are passed too, and must be ignored.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "options.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> lines;
  for (std::size_t begin = 0; begin <= input.size();) {
    const std::size_t end = std::min(input.find('\n', begin), input.size());
    lines.push_back(input.substr(begin, end - begin));
    begin = end + 1;
  }
  std::vector<char*> env;
  for (std::string& line : lines) env.push_back(line.data());  // a NUL in a line ends it, as in environ
  env.push_back(nullptr);
  std::string warnings;
  const glbudget::Options o = glbudget::parse_options(env.data(), &warnings);
  // The ranges the shim relies on.
  if (!(o.fps >= 0 && o.fps <= 10000) || o.select_frames < 1 || o.select_frames > 1000000 ||
      !(o.transition_s >= 0 && o.transition_s <= 3600))
    std::abort();
  return 0;
}
