// Framebuffers of the pipeline. Sizes are quality knobs: the scene targets follow the render
// scale, the shadow map its resolution; they are reallocated when a knob changes.
#pragma once
#include <GL/glew.h>

namespace demo {

// A framebuffer with colour textures and optionally a depth texture.
class Framebuffer {
 public:
  Framebuffer() = default;
  ~Framebuffer() { release(); }
  Framebuffer(const Framebuffer&) = delete;
  Framebuffer& operator=(const Framebuffer&) = delete;

  // (Re)allocates when the size differs; colour formats are GL internal formats, 0 = unused.
  void ensure(int width, int height, GLenum color0, GLenum color1, bool depth, bool depth_compare = false);
  void bind() const;  // binds the framebuffer and sets the viewport to its size
  GLuint color(int i) const { return colors_[i]; }
  GLuint depth() const { return depth_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  void release();
  GLuint fbo_ = 0, colors_[2] = {0, 0}, depth_ = 0;
  int width_ = 0, height_ = 0;
};

}  // namespace demo
