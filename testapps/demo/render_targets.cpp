#include "render_targets.hpp"

#include <stdexcept>
#include <string>

namespace demo {
namespace {

GLuint make_texture(int width, int height, GLenum internal_format, GLenum format, GLenum type, GLenum filter) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexImage2D(GL_TEXTURE_2D, 0, static_cast<GLint>(internal_format), width, height, 0, format, type, nullptr);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, static_cast<GLint>(filter));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, static_cast<GLint>(filter));
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return texture;
}

}  // namespace

void Framebuffer::ensure(int width, int height, GLenum color0, GLenum color1, bool depth, bool depth_compare) {
  if (fbo_ && width == width_ && height == height_) return;
  release();
  width_ = width;
  height_ = height;
  glGenFramebuffers(1, &fbo_);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  GLenum buffers[2];
  GLsizei count = 0;
  for (GLenum format : {color0, color1}) {
    if (!format) continue;
    const GLenum type = format == GL_RGBA8 ? GL_UNSIGNED_BYTE : GL_FLOAT;
    colors_[count] = make_texture(width, height, format, GL_RGBA, type, GL_LINEAR);
    buffers[count] = GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(count);
    glFramebufferTexture2D(GL_FRAMEBUFFER, buffers[count], GL_TEXTURE_2D, colors_[count], 0);
    ++count;
  }
  glDrawBuffers(count, buffers);
  if (count == 0) glReadBuffer(GL_NONE);
  if (depth) {
    depth_ = make_texture(width, height, GL_DEPTH_COMPONENT24, GL_DEPTH_COMPONENT, GL_FLOAT,
                          depth_compare ? GL_LINEAR : GL_NEAREST);
    if (depth_compare) {
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    }
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, depth_, 0);
  }
  const GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("incomplete framebuffer: status " + std::to_string(status));
  }
}

void Framebuffer::bind() const {
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, width_, height_);
}

void Framebuffer::release() {
  if (!fbo_) return;
  glDeleteFramebuffers(1, &fbo_);
  glDeleteTextures(2, colors_);
  glDeleteTextures(1, &depth_);
  fbo_ = depth_ = colors_[0] = colors_[1] = 0;
}

}  // namespace demo
