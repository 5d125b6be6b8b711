// A 2D texture made from pixels in memory, through a GL loader, for `glbudget ssim --gpu` and
// the GPU SSIM test. One mipmap level and GL's default sampling state.
#pragma once
#include "gpu_ssim.hpp"

namespace glbudget::cli {

class GlTexture {
 public:
  // glTexImage2D(GL_TEXTURE_2D, 0, internal_format, width, height, 0, format, type, pixels), rows
  // packed (alignment 1), the first row at t = 0. Throws std::runtime_error if GL refuses.
  GlTexture(GlProcLoader load, int width, int height, unsigned internal_format, unsigned format, unsigned type,
            const void* pixels);
  ~GlTexture();  // its context must be current
  GlTexture(const GlTexture&) = delete;
  GlTexture& operator=(const GlTexture&) = delete;

  unsigned name() const { return name_; }

 private:
  GlProcLoader load_;
  unsigned name_ = 0;
};

}  // namespace glbudget::cli
