#include "gpu_scene.hpp"

#include <cstddef>

namespace demo {

ScenePose ScenePose::at(const Scene& scene, double t) {
  ScenePose pose;
  for (const Object& o : scene.objects) {
    pose.object_transforms.push_back(o.animation ? o.animation(t).matrix() : o.transform.matrix());
  }
  for (const Skeleton& s : scene.skeletons) pose.skeleton_bones.push_back(s.pose(t));
  return pose;
}

GpuScene::GpuScene(const Scene& scene) : scene_(scene) {
  glGenVertexArrays(1, &vao_);
  glBindVertexArray(vao_);
  glGenBuffers(1, &vertex_buffer_);
  glBindBuffer(GL_ARRAY_BUFFER, vertex_buffer_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(scene.geometry.vertices.size() * sizeof(Vertex)),
               scene.geometry.vertices.data(), GL_STATIC_DRAW);
  glGenBuffers(1, &index_buffer_);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, index_buffer_);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(scene.geometry.indices.size() * sizeof(uint32_t)),
               scene.geometry.indices.data(), GL_STATIC_DRAW);
  const auto offset = [](size_t bytes) { return reinterpret_cast<const void*>(bytes); };
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), offset(offsetof(Vertex, position)));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex), offset(offsetof(Vertex, normal)));
  glEnableVertexAttribArray(2);
  glVertexAttribIPointer(2, 2, GL_UNSIGNED_BYTE, sizeof(Vertex), offset(offsetof(Vertex, bones)));
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, sizeof(Vertex), offset(offsetof(Vertex, weight)));
  glBindVertexArray(0);
}

GpuScene::~GpuScene() {
  glDeleteBuffers(1, &index_buffer_);
  glDeleteBuffers(1, &vertex_buffer_);
  glDeleteVertexArrays(1, &vao_);
}

int GpuScene::draw(const ScenePose& pose, const std::function<bool(const Object&)>& filter, const Program& rigid,
                   const Program& skinned, const std::function<void(const Program&, const Object&)>& per_object) const {
  glBindVertexArray(vao_);
  int draws = 0;
  for (size_t i = 0; i < scene_.objects.size(); ++i) {
    const Object& object = scene_.objects[i];
    if (!filter(object)) continue;
    const Program& program = object.skeleton >= 0 ? skinned : rigid;
    program.use();
    glUniformMatrix4fv(program.uniform("u_model"), 1, GL_FALSE, pose.object_transforms[i].data());
    if (object.skeleton >= 0) {
      const auto& bones = pose.skeleton_bones[static_cast<size_t>(object.skeleton)];
      glUniformMatrix4fv(program.uniform("u_bones"), static_cast<GLsizei>(bones.size()), GL_FALSE,
                         bones.front().data());
    }
    if (per_object) per_object(program, object);
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(object.index_count), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(static_cast<size_t>(object.first_index) * sizeof(uint32_t)));
    ++draws;
  }
  glBindVertexArray(0);
  return draws;
}

}  // namespace demo
