#include "renderer.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace demo {
namespace {

// Light 0's view-projection: an orthographic box around the shadowed region for the sun,
// a perspective frustum covering the cone for a spot or point light.
Eigen::Matrix4f shadow_view_projection(const Scene& scene) {
  const Light& light = scene.lights.front();
  if (light.type == Light::Type::Directional) {
    const float r = scene.shadow_radius;
    const Eigen::Vector3f eye = scene.shadow_centre - light.direction * (2.0f * r);
    return orthographic(r, r, 0.1f * r, 4.0f * r) * look_at(eye, scene.shadow_centre);
  }
  const float fov = light.type == Light::Type::Spot ? std::min(2.0f * light.cone_deg + 10.0f, 160.0f) : 160.0f;
  return perspective(fov, 1.0f, 0.2f, scene.far_plane) * look_at(light.position, light.position + light.direction);
}

}  // namespace

const char* pass_name(Pass pass) {
  static const char* const names[kPassCount] = {"shadows", "base", "metals", "reflections", "upscale", "antialiasing"};
  return names[static_cast<int>(pass)];
}

int FrameDraws::total() const { return std::accumulate(draws.begin(), draws.end(), 0); }

Renderer::Renderer(const Scene& scene, int window_width, int window_height, int shadow_size)
    : scene_(scene), width_(window_width), height_(window_height), shadow_size_(shadow_size), gpu_(scene) {}

FrameDraws Renderer::render(const Config& config, double time, PassObserver* observer) {
  const ScenePose pose = ScenePose::at(scene_, time);
  const CameraPose camera = scene_.camera(time);
  const float aspect = static_cast<float>(width_) / static_cast<float>(height_);
  FrameContext frame{scene_, gpu_, pose, config, {}, {}, {}, {}, {}, camera.eye, width_, height_, shadow_size_};
  frame.view = look_at(camera.eye, camera.target);
  frame.projection = perspective(camera.vertical_fov_deg, aspect, 0.1f, scene_.far_plane);
  frame.inverse_projection = frame.projection.inverse();
  frame.view_projection = frame.projection * frame.view;
  frame.shadow_view_projection = shadow_view_projection(scene_);

  // The render-scale knob: the size of the scene framebuffers.
  const float scale = render_scale(config);
  const int scene_width = std::max(1, static_cast<int>(std::lround(width_ * scale)));
  const int scene_height = std::max(1, static_cast<int>(std::lround(height_ * scale)));
  const auto level = static_cast<size_t>(config[Knob::Resolution]);
  Framebuffer& scene_target = scene_targets_[level];
  scene_target.ensure(scene_width, scene_height, GL_RGBA16F, GL_RGBA16F, true);

  FrameDraws result;
  const auto run = [&](Pass pass, auto&& draw) {
    if (observer) observer->pass_begin(pass);
    result.draws[static_cast<int>(pass)] = draw();
    if (observer) observer->pass_end(pass);
  };
  run(Pass::Shadows, [&] { return shadows_.run(frame); });
  run(Pass::Base, [&] { return base_.run(frame, scene_target, shadows_.shadow_map()); });
  if (scene_.has_metals()) run(Pass::Metals, [&] { return metals_.run(frame, scene_target, shadows_.shadow_map()); });
  GLuint hdr = scene_target.color(0);
  if (reflection_samples(config) > 0 && scene_.has_reflective_surfaces()) {
    Framebuffer& reflected = reflected_targets_[level];
    reflected.ensure(scene_width, scene_height, GL_RGBA16F, 0, false);
    run(Pass::Reflections, [&] { return reflections_.run(frame, scene_target, reflected); });
    hdr = reflected.color(0);
  }
  const bool antialiasing = fxaa_steps(config) > 0;
  if (antialiasing) post_.ensure(width_, height_, GL_RGBA8, 0, false);
  run(Pass::Upscale, [&] { return upscale_.run(frame, hdr, antialiasing ? &post_ : nullptr); });
  if (antialiasing) run(Pass::Antialiasing, [&] { return fxaa_.run(frame, post_.color(0)); });
  return result;
}

std::vector<uint8_t> Renderer::read_pixels() const {
  const auto row = static_cast<size_t>(width_) * 3;
  std::vector<uint8_t> bottom_up(row * static_cast<size_t>(height_));
  glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width_, height_, GL_RGB, GL_UNSIGNED_BYTE, bottom_up.data());
  std::vector<uint8_t> top_down(bottom_up.size());
  for (int y = 0; y < height_; ++y) {
    std::copy_n(bottom_up.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(height_ - 1 - y)), row,
                top_down.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(y)));
  }
  return top_down;
}

}  // namespace demo
