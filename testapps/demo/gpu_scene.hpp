// A scene's geometry in GPU buffers (one VAO) and the per-frame state of its objects.
#pragma once
#include <GL/glew.h>

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "gl_program.hpp"
#include "scene.hpp"

namespace demo {

// Where every object is at time t: rigid transforms and skinning matrices.
struct ScenePose {
  std::vector<Eigen::Matrix4f> object_transforms;
  std::vector<std::vector<Eigen::Matrix4f>> skeleton_bones;
  static ScenePose at(const Scene& scene, double t);
};

class GpuScene {
 public:
  explicit GpuScene(const Scene& scene);
  ~GpuScene();
  GpuScene(const GpuScene&) = delete;
  GpuScene& operator=(const GpuScene&) = delete;

  // Draws the objects accepted by `filter` with `rigid` or `skinned` (same uniforms),
  // setting u_model, u_bones and, through `per_object`, material uniforms.
  // Returns the number of draw calls issued.
  int draw(const ScenePose& pose, const std::function<bool(const Object&)>& filter, const Program& rigid,
           const Program& skinned, const std::function<void(const Program&, const Object&)>& per_object) const;

 private:
  const Scene& scene_;
  GLuint vao_ = 0, vertex_buffer_ = 0, index_buffer_ = 0;
};

}  // namespace demo
