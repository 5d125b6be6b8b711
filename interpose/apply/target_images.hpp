// What the render-target scaler's own files (render_targets.cpp, blit_warmup.cpp) share: the
// sizes and buffers of the images they store, and the real bindings a blit between them touches.
#pragma once
#include <algorithm>
#include <cmath>

#include "gl_types.hpp"

namespace glbudget::target_images {

inline GLsizei scaled(GLsizei size, double scale) {
  return std::max<GLsizei>(1, static_cast<GLsizei>(std::lround(size * scale)));
}

inline bool is_depth(GLint f) {
  return f == GL_DEPTH_COMPONENT || f == GL_DEPTH_COMPONENT16 || f == GL_DEPTH_COMPONENT24 ||
         f == GL_DEPTH_COMPONENT32 || f == GL_DEPTH_COMPONENT32F;
}
inline bool is_depth_stencil(GLint f) {
  return f == GL_DEPTH_STENCIL || f == GL_DEPTH24_STENCIL8 || f == GL_DEPTH32F_STENCIL8;
}
// The buffers an image of `format` holds, and the framebuffer point it attaches to.
inline GLbitfield buffer_bits(GLint format) {
  if (is_depth(format)) return GL_DEPTH_BUFFER_BIT;
  if (is_depth_stencil(format)) return GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT;
  if (format == GL_STENCIL_INDEX8) return GL_STENCIL_BUFFER_BIT;
  return GL_COLOR_BUFFER_BIT;
}
inline GLenum attachment_point(GLint format) {
  switch (buffer_bits(format)) {
    case GL_DEPTH_BUFFER_BIT:
      return GL_DEPTH_ATTACHMENT;
    case GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT:
      return GL_DEPTH_STENCIL_ATTACHMENT;
    case GL_STENCIL_BUFFER_BIT:
      return GL_STENCIL_ATTACHMENT;
    default:
      return GL_COLOR_ATTACHMENT0;
  }
}
inline bool is_integer_format(GLenum format) {
  return format == GL_RED_INTEGER || format == GL_RG_INTEGER || format == GL_RGB_INTEGER || format == GL_RGBA_INTEGER ||
         format == GL_BGRA_INTEGER;
}
// The filter a rescale stretches an image of this format with: colour linear, the rest (and
// integer colour, which cannot be filtered) nearest.
inline GLenum stretch_filter(GLint internal_format, GLenum format) {
  return buffer_bits(internal_format) == GL_COLOR_BUFFER_BIT && !is_integer_format(format) ? GL_LINEAR : GL_NEAREST;
}

// The real bindings a rescale touches, restored when it ends: the framebuffers, the
// renderbuffer, the texture of `kind` on the active unit, no pixel-unpack buffer, no scissor.
struct SavedBindings {
  GLint draw = 0, read = 0, texture = 0, renderbuffer = 0, unpack = 0;
  GLenum kind = GL_TEXTURE_2D;
  bool scissor = false;
  explicit SavedBindings(GLenum texture_kind = GL_TEXTURE_2D);
  ~SavedBindings();
  SavedBindings(const SavedBindings&) = delete;
  SavedBindings& operator=(const SavedBindings&) = delete;
  static void* bind_buffer();
};

}  // namespace glbudget::target_images
