// How shaders and programs are named: in the frame log's pass column, in the GLBUDGET_DUMP
// index, and (later) in the variant manifest. The same hashes everywhere.
#pragma once
#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <string>
#include <vector>

#include "frame_row.hpp"
#include "gl_types.hpp"
#include "stable_hash.hpp"

namespace glbudget {

inline uint64_t shader_hash(GLenum stage, const std::string& source) {
  return fnv1a(source, fnv1a_u64(stage, kFnvOffset));
}

// A pass is named by its shaders: the hashes of (stage, source) of each, order-independent.
inline PassId program_hash(std::vector<uint64_t> shader_hashes) {
  std::sort(shader_hashes.begin(), shader_hashes.end());
  uint64_t h = fnv1a("program");
  for (uint64_t s : shader_hashes) h = fnv1a_u64(s, h);
  return h == kFixedFunctionPass ? 1 : h;
}

// 16 hex digits, as in the frame log.
inline std::string hash_text(uint64_t h) {
  char text[17];
  std::snprintf(text, sizeof text, "%016" PRIx64, h);
  return text;
}

}  // namespace glbudget
