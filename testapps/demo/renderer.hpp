// The frame: shadows -> base -> metals -> reflections -> upscale -> antialiasing, drawn into
// the default framebuffer of the current context at the window size.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include "config.hpp"
#include "gpu_scene.hpp"
#include "passes/passes.hpp"
#include "render_targets.hpp"
#include "scene.hpp"

namespace demo {

// Told where each pass starts and ends, e.g. to wrap it in GL queries. A pass that has
// nothing to draw in the scene or is switched off is not run and not reported.
class PassObserver {
 public:
  virtual ~PassObserver() = default;
  virtual void pass_begin(Pass pass) = 0;
  virtual void pass_end(Pass pass) = 0;
};

struct FrameDraws {
  std::array<int, kPassCount> draws{};  // draw calls per pass (index: Pass)
  int total() const;
};

class Renderer {
 public:
  Renderer(const Scene& scene, int window_width, int window_height, int shadow_size = kShadowMapSize);

  FrameDraws render(const Config& config, double time, PassObserver* observer = nullptr);
  // The default framebuffer as RGB8, top row first (read before the buffer swap).
  std::vector<uint8_t> read_pixels() const;
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  const Scene& scene_;
  int width_, height_, shadow_size_;
  GpuScene gpu_;
  ShadowPass shadows_;
  BasePass base_;
  MetalsPass metals_;
  ReflectionsPass reflections_;
  UpscalePass upscale_;
  FxaaPass fxaa_;
  // Scene-sized targets per resolution level, so switching levels costs no reallocation.
  std::array<Framebuffer, kLevelCount> scene_targets_, reflected_targets_;
  Framebuffer post_;
};

}  // namespace demo
