// The environment the metals pass integrates: a cube map baked on the CPU from the scene's
// sky and ground colours (a studio-like sky with bright panels, so that few samples visibly
// alias). Sampling a texture per sample, as an engine's importance-sampled IBL does, is what
// makes the metals level show in texel accesses as well as in instructions.
#pragma once
#include <GL/glew.h>

#include <Eigen/Core>

namespace demo {

class EnvironmentMap {
 public:
  static constexpr int kFaceSize = 64;
  EnvironmentMap() = default;
  EnvironmentMap(const EnvironmentMap&) = delete;
  EnvironmentMap& operator=(const EnvironmentMap&) = delete;
  ~EnvironmentMap();
  // The cube map for these colours, rebaked only when they change.
  GLuint texture(const Eigen::Vector3f& sky, const Eigen::Vector3f& ground);

  // Radiance from direction d (need not be normalised): the function the map is baked from.
  static Eigen::Vector3f radiance(const Eigen::Vector3f& d, const Eigen::Vector3f& sky, const Eigen::Vector3f& ground);

 private:
  GLuint texture_ = 0;
  Eigen::Vector3f sky_, ground_;
};

}  // namespace demo
