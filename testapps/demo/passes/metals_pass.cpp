#include "passes/lighting_uniforms.hpp"
#include "passes/passes.hpp"
#include "shaders_embedded.hpp"

#include <string>

namespace demo {

MetalsPass::MetalsPass() {
  for (int level = 0; level < 3; ++level) {
    Config config;
    config[Knob::Metals] = level;
    const Defines rigid{{"METAL_SAMPLES", std::to_string(metal_samples(config))}};
    Defines skinned = rigid;
    skinned.emplace_back("SKINNED", "1");
    rigid_[level] = std::make_unique<Program>(std::vector{shaders::scene_vert},
                                              std::vector{shaders::lighting_glsl, shaders::metal_frag}, rigid);
    skinned_[level] = std::make_unique<Program>(std::vector{shaders::scene_vert},
                                                std::vector{shaders::lighting_glsl, shaders::metal_frag}, skinned);
  }
}

int MetalsPass::run(const FrameContext& frame, const Framebuffer& scene_target, GLuint shadow_map) {
  scene_target.bind();
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  const int level = frame.config[Knob::Metals];  // the quality knob: a #define
  const GLuint environment = environment_.texture(frame.scene.sky, frame.scene.ground);
  for (const Program* program : {rigid_[level].get(), skinned_[level].get()}) {
    set_lighting_uniforms(*program, frame, shadow_map);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_CUBE_MAP, environment);
    glUniform1i(program->uniform("u_environment"), 1);
  }
  glActiveTexture(GL_TEXTURE0);
  return frame.gpu.draw(
      frame.pose, [](const Object& o) { return o.material.metal; }, *rigid_[level], *skinned_[level],
      set_material_uniforms);
}

}  // namespace demo
