#include "passes/passes.hpp"
#include "shaders_embedded.hpp"

namespace demo {

UpscalePass::UpscalePass() : program_({shaders::fullscreen_vert}, {shaders::upscale_frag}) {}

int UpscalePass::run(const FrameContext& frame, GLuint scene_color, const Framebuffer* output) {
  if (output) {
    output->bind();
  } else {
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, frame.window_width, frame.window_height);
  }
  program_.use();
  bind_texture(program_.uniform("u_scene"), 0, scene_color);
  return triangle_.draw();
}

}  // namespace demo
