// Stable 64-bit hashes (FNV-1a) that name shaders and programs across runs and machines.
#pragma once
#include <cstdint>
#include <string_view>

namespace glbudget {

constexpr uint64_t kFnvOffset = 0xcbf29ce484222325ull;

inline uint64_t fnv1a(std::string_view bytes, uint64_t h = kFnvOffset) {
  for (unsigned char c : bytes) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

inline uint64_t fnv1a_u64(uint64_t v, uint64_t h) {
  for (int i = 0; i < 8; ++i) h = fnv1a(std::string_view(reinterpret_cast<const char*>(&v) + i, 1), h);
  return h;
}

}  // namespace glbudget
