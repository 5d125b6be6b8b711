#include "passes/fullscreen.hpp"
#include "passes/passes.hpp"
#include "shaders_embedded.hpp"

namespace demo {

ReflectionsPass::ReflectionsPass() : program_({shaders::fullscreen_vert}, {shaders::ssr_frag}) {}

int ReflectionsPass::run(const FrameContext& frame, const Framebuffer& scene_target, const Framebuffer& output) {
  output.bind();
  program_.use();
  bind_texture(program_.uniform("u_color"), 0, scene_target.color(0));
  bind_texture(program_.uniform("u_normal_reflectivity"), 1, scene_target.color(1));
  bind_texture(program_.uniform("u_depth"), 2, scene_target.depth());
  glUniformMatrix4fv(program_.uniform("u_projection"), 1, GL_FALSE, frame.projection.data());
  glUniformMatrix4fv(program_.uniform("u_inverse_projection"), 1, GL_FALSE, frame.inverse_projection.data());
  // The quality knobs: uniforms.
  glUniform1i(program_.uniform("u_samples"), reflection_samples(frame.config));
  glUniform1i(program_.uniform("u_kernel_taps"), reflection_kernel_taps(frame.config));
  glUniform1f(program_.uniform("u_max_distance"), frame.scene.reflection_distance);
  return triangle_.draw();
}

}  // namespace demo
