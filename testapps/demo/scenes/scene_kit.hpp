// Small helpers shared by the scene generators.
#pragma once
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "scene.hpp"

namespace demo::kit {

// Triangle budget of an object at the given --detail, never below a minimal shape.
inline int scaled(int full_triangles, float detail) {
  return std::max(12, static_cast<int>(std::lround(full_triangles * detail)));
}

// Deterministic pseudo-random numbers (SplitMix64): the same on every platform and run.
class Rng {
 public:
  explicit Rng(uint64_t seed) : state_(seed) {}
  float uniform(float lo = 0.0f, float hi = 1.0f) {
    state_ += 0x9E3779B97F4A7C15ull;
    uint64_t z = state_;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return lo + (hi - lo) * static_cast<float>(z >> 40) / static_cast<float>(1ull << 24);
  }

 private:
  uint64_t state_;
};

inline Eigen::Affine3f at(float x, float y, float z, float yaw = 0.0f, float scale = 1.0f) {
  return Eigen::Translation3f(x, y, z) * Eigen::AngleAxisf(yaw, Eigen::Vector3f::UnitY()) * Eigen::Scaling(scale);
}

inline Material matte(float r, float g, float b, float roughness = 0.7f) {
  return Material{{r, g, b}, roughness, false, 0.0f};
}
inline Material reflective(float r, float g, float b, float roughness, float reflectivity) {
  return Material{{r, g, b}, roughness, false, reflectivity};
}
inline Material metal(float r, float g, float b, float roughness) { return Material{{r, g, b}, roughness, true, 0.0f}; }

}  // namespace demo::kit
