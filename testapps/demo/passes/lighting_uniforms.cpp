#include "passes/lighting_uniforms.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

namespace demo {

void set_lighting_uniforms(const Program& program, const FrameContext& frame, GLuint shadow_map) {
  program.use();
  const auto& lights = frame.scene.lights;
  const int count = std::min<int>(static_cast<int>(lights.size()), 4);  // MAX_LIGHTS in lighting.glsl
  std::vector<float> positions, directions, colors;
  for (int i = 0; i < count; ++i) {
    const Light& light = lights[static_cast<size_t>(i)];
    const bool positional = light.type != Light::Type::Directional;
    const float cos_cone =
        light.type == Light::Type::Spot ? std::cos(light.cone_deg * std::numbers::pi_v<float> / 180.0f) : -2.0f;
    positions.insert(positions.end(),
                     {light.position.x(), light.position.y(), light.position.z(), positional ? 1.0f : 0.0f});
    directions.insert(directions.end(), {light.direction.x(), light.direction.y(), light.direction.z(), cos_cone});
    colors.insert(colors.end(), {light.color.x(), light.color.y(), light.color.z()});
  }
  glUniform1i(program.uniform("u_light_count"), count);
  glUniform4fv(program.uniform("u_light_position"), count, positions.data());
  glUniform4fv(program.uniform("u_light_direction"), count, directions.data());
  glUniform3fv(program.uniform("u_light_color"), count, colors.data());
  glUniform3fv(program.uniform("u_sky"), 1, frame.scene.sky.data());
  glUniform3fv(program.uniform("u_ground"), 1, frame.scene.ground.data());
  glUniform3fv(program.uniform("u_eye"), 1, frame.eye.data());
  glUniformMatrix4fv(program.uniform("u_view"), 1, GL_FALSE, frame.view.data());
  glUniformMatrix4fv(program.uniform("u_view_projection"), 1, GL_FALSE, frame.view_projection.data());
  // Clip space [-1, 1] -> texture space [0, 1].
  Eigen::Matrix4f bias = Eigen::Matrix4f::Identity() * 0.5f;
  bias.col(3) = Eigen::Vector4f(0.5f, 0.5f, 0.5f, 1.0f);
  const Eigen::Matrix4f shadow_matrix = bias * frame.shadow_view_projection;
  glUniformMatrix4fv(program.uniform("u_shadow_matrix"), 1, GL_FALSE, shadow_matrix.data());
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, shadow_map);
  glUniform1i(program.uniform("u_shadow_map"), 0);
}

void set_material_uniforms(const Program& program, const Object& object) {
  const Material& material = object.material;
  glUniform3fv(program.uniform("u_albedo"), 1, material.albedo.data());
  glUniform1f(program.uniform("u_roughness"), material.roughness);
  glUniform1f(program.uniform("u_reflectivity"), material.reflectivity);
}

}  // namespace demo
