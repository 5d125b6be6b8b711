// The six passes of the paper's renderer (Table 2). Each owns its programs and its targets,
// and returns the number of draw calls it issued.
#pragma once
#include <GL/glew.h>

#include <array>
#include <memory>

#include "gl_program.hpp"
#include "passes/environment_map.hpp"
#include "passes/frame_context.hpp"
#include "passes/fullscreen.hpp"
#include "render_targets.hpp"

namespace demo {

// Depth from light 0 into a shadow map of shadow_map_size(config) texels square. One map per
// level is kept, so switching levels costs no reallocation.
class ShadowPass {
 public:
  ShadowPass();
  int run(const FrameContext& frame);
  GLuint shadow_map() const { return current_->depth(); }

 private:
  Program rigid_, skinned_;
  std::array<Framebuffer, kLevelCount> targets_;
  const Framebuffer* current_ = &targets_[0];
};

// Every non-metallic object, shaded with SHADING_MODEL = shading_model(config).
// Clears and fills the scene target (lit colour, view normal + reflectivity, depth).
class BasePass {
 public:
  BasePass();
  int run(const FrameContext& frame, const Framebuffer& scene_target, GLuint shadow_map);

 private:
  std::array<std::unique_ptr<Program>, 3> rigid_, skinned_;  // by shading model
};

// Metallic objects with METAL_SAMPLES = metal_samples(config), into the same scene target.
class MetalsPass {
 public:
  MetalsPass();
  int run(const FrameContext& frame, const Framebuffer& scene_target, GLuint shadow_map);

 private:
  std::array<std::unique_ptr<Program>, 3> rigid_, skinned_;  // by quality level
  EnvironmentMap environment_;
};

// Screen-space reflections (u_samples, u_kernel_taps) from the scene target into `output`.
class ReflectionsPass {
 public:
  ReflectionsPass();
  int run(const FrameContext& frame, const Framebuffer& scene_target, const Framebuffer& output);

 private:
  Program program_;
  FullscreenTriangle triangle_;
};

// Render scale: bilinear upscale of the scene image to window size, with tone mapping.
// Draws into `output`, or the default framebuffer when it is null.
class UpscalePass {
 public:
  UpscalePass();
  int run(const FrameContext& frame, GLuint scene_color, const Framebuffer* output);

 private:
  Program program_;
  FullscreenTriangle triangle_;
};

// FXAA with FXAA_STEPS = fxaa_steps(config) into the default framebuffer.
class FxaaPass {
 public:
  FxaaPass();
  int run(const FrameContext& frame, GLuint image);

 private:
  std::array<std::unique_ptr<Program>, 2> programs_;  // 32 and 2 steps
  FullscreenTriangle triangle_;
};

}  // namespace demo
