// The GL state GpuSsim's commands change, saved and restored around them: it runs in other
// people's contexts, between their draws, and must leave every binding as it found it.
#pragma once
#include "gpu_ssim_gl.hpp"

namespace glbudget::gpu_ssim_detail {

// The texture units (images A and B) and shader-storage bindings GpuSsim's shaders use.
inline constexpr GLuint kUnitA = 0, kUnitB = 1;
inline constexpr GLuint kLumaBinding = 0, kPartialsBinding = 1, kResultBinding = 2;

// Saves, on construction: the current program, GL_ACTIVE_TEXTURE, the 2D texture and the
// sampler of units kUnitA and kUnitB, the indexed and generic GL_SHADER_STORAGE_BUFFER bindings
// 0..2, and GL_COPY_READ_BUFFER. Restores them all on destruction.
class SavedGlState {
 public:
  explicit SavedGlState(const GlFunctions& gl);
  ~SavedGlState();
  SavedGlState(const SavedGlState&) = delete;
  SavedGlState& operator=(const SavedGlState&) = delete;

 private:
  struct Unit {
    GLint texture = 0, sampler = 0;
  };
  struct Storage {
    GLint buffer = 0;
    GLint64 start = 0, size = 0;
  };
  const GlFunctions& gl_;
  GLint program_ = 0, active_texture_ = GL_TEXTURE0;
  Unit units_[2];
  Storage storage_[3];
  GLint generic_storage_ = 0, copy_read_ = 0;
};

}  // namespace glbudget::gpu_ssim_detail
