#include "passes/lighting_uniforms.hpp"
#include "passes/passes.hpp"
#include "shaders_embedded.hpp"

#include <string>

namespace demo {

BasePass::BasePass() {
  for (int model = 0; model < 3; ++model) {
    const Defines rigid{{"SHADING_MODEL", std::to_string(model)}};
    Defines skinned = rigid;
    skinned.emplace_back("SKINNED", "1");
    rigid_[model] = std::make_unique<Program>(std::vector{shaders::scene_vert},
                                              std::vector{shaders::lighting_glsl, shaders::base_frag}, rigid);
    skinned_[model] = std::make_unique<Program>(std::vector{shaders::scene_vert},
                                                std::vector{shaders::lighting_glsl, shaders::base_frag}, skinned);
  }
}

int BasePass::run(const FrameContext& frame, const Framebuffer& scene_target, GLuint shadow_map) {
  scene_target.bind();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const float background[4] = {frame.scene.sky.x(), frame.scene.sky.y(), frame.scene.sky.z(), 1.0f};
  const float no_normal[4] = {0.0f, 0.0f, 0.0f, 0.0f};
  glClearBufferfv(GL_COLOR, 0, background);
  glClearBufferfv(GL_COLOR, 1, no_normal);
  glClear(GL_DEPTH_BUFFER_BIT);
  const int model = shading_model(frame.config);  // the quality knob: a #define
  set_lighting_uniforms(*rigid_[model], frame, shadow_map);
  set_lighting_uniforms(*skinned_[model], frame, shadow_map);
  return frame.gpu.draw(
      frame.pose, [](const Object& o) { return !o.material.metal; }, *rigid_[model], *skinned_[model],
      set_material_uniforms);
}

}  // namespace demo
