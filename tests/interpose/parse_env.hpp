// Test helper: parse_options() on an environment given as "NAME=value" strings.
#pragma once
#include <string>
#include <vector>

#include "options.hpp"

inline glbudget::Options parse_env(std::vector<std::string> vars, std::string* warnings) {
  std::vector<char*> env;
  for (auto& v : vars) env.push_back(v.data());
  env.push_back(nullptr);
  return glbudget::parse_options(env.data(), warnings);
}
