#include "passes/passes.hpp"
#include "shaders_embedded.hpp"

namespace demo {

ShadowPass::ShadowPass()
    : rigid_({shaders::scene_vert}, {shaders::depth_frag}),
      skinned_({shaders::scene_vert}, {shaders::depth_frag}, {{"SKINNED", "1"}}) {}

int ShadowPass::run(const FrameContext& frame) {
  const int size = shadow_map_size(frame.config, frame.shadow_size);  // the quality knob: a texture size
  Framebuffer& target = targets_[static_cast<size_t>(frame.config[Knob::Shadows])];
  target.ensure(size, size, 0, 0, true, true);
  target.bind();
  current_ = &target;
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(2.0f, 2.0f);  // slope-scaled bias against shadow acne
  for (const Program* program : {&rigid_, &skinned_}) {
    program->use();
    glUniformMatrix4fv(program->uniform("u_view_projection"), 1, GL_FALSE, frame.shadow_view_projection.data());
  }
  const int draws = frame.gpu.draw(
      frame.pose, [](const Object&) { return true; }, rigid_, skinned_, nullptr);
  glDisable(GL_POLYGON_OFFSET_FILL);
  return draws;
}

}  // namespace demo
