#include "passes/passes.hpp"
#include "shaders_embedded.hpp"

#include <string>

namespace demo {

FxaaPass::FxaaPass() {
  for (int level = 0; level < 2; ++level) {
    Config config;
    config[Knob::Antialiasing] = level;
    programs_[level] = std::make_unique<Program>(std::vector{shaders::fullscreen_vert}, std::vector{shaders::fxaa_frag},
                                                 Defines{{"FXAA_STEPS", std::to_string(fxaa_steps(config))}});
  }
}

int FxaaPass::run(const FrameContext& frame, GLuint image) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  glViewport(0, 0, frame.window_width, frame.window_height);
  const Program& program = *programs_[frame.config[Knob::Antialiasing]];  // the knob: a #define
  program.use();
  bind_texture(program.uniform("u_image"), 0, image);
  return triangle_.draw();
}

}  // namespace demo
