// What every pass needs to know about the frame being drawn.
#pragma once
#include <Eigen/Core>

#include "config.hpp"
#include "gpu_scene.hpp"
#include "scene.hpp"

namespace demo {

enum class Pass { Shadows, Base, Metals, Reflections, Upscale, Antialiasing };
inline constexpr int kPassCount = 6;
const char* pass_name(Pass pass);  // "shadows", "base", ...

struct FrameContext {
  const Scene& scene;
  const GpuScene& gpu;
  const ScenePose& pose;
  const Config& config;
  Eigen::Matrix4f view, projection, inverse_projection, view_projection;
  Eigen::Matrix4f shadow_view_projection;  // light 0's clip space
  Eigen::Vector3f eye;
  int window_width = 0, window_height = 0;
  int shadow_size = kShadowMapSize;  // the shadow map's side at the best level
};

}  // namespace demo
