#include "gpu_ssim_state.hpp"

namespace glbudget::gpu_ssim_detail {

namespace {
constexpr GLuint kUnits[2] = {kUnitA, kUnitB};
}  // namespace

SavedGlState::SavedGlState(const GlFunctions& gl) : gl_(gl) {
  gl.GetIntegerv(GL_CURRENT_PROGRAM, &program_);
  gl.GetIntegerv(GL_ACTIVE_TEXTURE, &active_texture_);
  for (int i = 0; i < 2; ++i) {
    gl.ActiveTexture(GL_TEXTURE0 + kUnits[i]);
    gl.GetIntegerv(GL_TEXTURE_BINDING_2D, &units_[i].texture);
    gl.GetIntegerv(GL_SAMPLER_BINDING, &units_[i].sampler);
  }
  gl.ActiveTexture(static_cast<GLenum>(active_texture_));
  for (GLuint i = 0; i < 3; ++i) {
    gl.GetIntegeri_v(GL_SHADER_STORAGE_BUFFER_BINDING, i, &storage_[i].buffer);
    gl.GetInteger64i_v(GL_SHADER_STORAGE_BUFFER_START, i, &storage_[i].start);
    gl.GetInteger64i_v(GL_SHADER_STORAGE_BUFFER_SIZE, i, &storage_[i].size);
  }
  gl.GetIntegerv(GL_SHADER_STORAGE_BUFFER_BINDING, &generic_storage_);
  gl.GetIntegerv(GL_COPY_READ_BUFFER_BINDING, &copy_read_);
}

SavedGlState::~SavedGlState() {
  const GlFunctions& gl = gl_;
  gl.UseProgram(static_cast<GLuint>(program_));
  for (int i = 0; i < 2; ++i) {
    gl.ActiveTexture(GL_TEXTURE0 + kUnits[i]);
    gl.BindTexture(GL_TEXTURE_2D, static_cast<GLuint>(units_[i].texture));
    gl.BindSampler(kUnits[i], static_cast<GLuint>(units_[i].sampler));
  }
  gl.ActiveTexture(static_cast<GLenum>(active_texture_));
  for (GLuint i = 0; i < 3; ++i) {
    const Storage& s = storage_[i];
    // Start and size read 0 after glBindBufferBase (and with nothing bound): bound whole.
    if (s.buffer == 0 || (s.start == 0 && s.size == 0))
      gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, i, static_cast<GLuint>(s.buffer));
    else
      gl.BindBufferRange(GL_SHADER_STORAGE_BUFFER, i, static_cast<GLuint>(s.buffer), static_cast<GLintptr>(s.start),
                         static_cast<GLsizeiptr>(s.size));
  }
  // Last: binding an indexed target also sets the generic binding.
  gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(generic_storage_));
  gl.BindBuffer(GL_COPY_READ_BUFFER, static_cast<GLuint>(copy_read_));
}

}  // namespace glbudget::gpu_ssim_detail
