#include "passes/lighting_uniforms.h"
#include "passes/passes.h"
#include "shaders_embedded.h"

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
  set_lighting_uniforms(*rigid_[level], frame, shadow_map);
  set_lighting_uniforms(*skinned_[level], frame, shadow_map);
  return frame.gpu.draw(frame.pose, [](const Object& o) { return o.material.metal; }, *rigid_[level],
                        *skinned_[level], set_material_uniforms);
}

}  // namespace demo
