// The shader corpus of tests/instrument/shaders.
#pragma once

#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace glbudget::test {

inline std::string shader_file(const std::string& name) {
  const std::string path = std::string(GLBUDGET_SOURCE_DIR) + "/tests/instrument/shaders/" + name;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace glbudget::test
