#include "gl_texture.hpp"

#include <GL/glcorearb.h>

#include <stdexcept>
#include <string>

namespace glbudget::cli {

namespace {

template <typename T>
T entry(GlProcLoader load, const char* name) {
  auto function = reinterpret_cast<T>(load(name));
  if (!function) throw std::runtime_error(std::string("no ") + name + " in this OpenGL");
  return function;
}

}  // namespace

GlTexture::GlTexture(GlProcLoader load, int width, int height, unsigned internal_format, unsigned format, unsigned type,
                     const void* pixels)
    : load_(load) {
  const auto get_integer = entry<PFNGLGETINTEGERVPROC>(load, "glGetIntegerv");
  const auto bind = entry<PFNGLBINDTEXTUREPROC>(load, "glBindTexture");
  const auto pixel_store = entry<PFNGLPIXELSTOREIPROC>(load, "glPixelStorei");
  const auto get_error = entry<PFNGLGETERRORPROC>(load, "glGetError");
  GLint bound = 0, alignment = 4, unpack_buffer = 0;
  get_integer(GL_TEXTURE_BINDING_2D, &bound);
  get_integer(GL_UNPACK_ALIGNMENT, &alignment);
  get_integer(GL_PIXEL_UNPACK_BUFFER_BINDING, &unpack_buffer);
  while (get_error() != GL_NO_ERROR) {
  }
  entry<PFNGLGENTEXTURESPROC>(load, "glGenTextures")(1, &name_);
  bind(GL_TEXTURE_2D, name_);
  pixel_store(GL_UNPACK_ALIGNMENT, 1);
  entry<PFNGLBINDBUFFERPROC>(load, "glBindBuffer")(GL_PIXEL_UNPACK_BUFFER, 0);
  entry<PFNGLTEXIMAGE2DPROC>(load, "glTexImage2D")(GL_TEXTURE_2D, 0, static_cast<GLint>(internal_format), width, height,
                                                   0, format, type, pixels);
  const GLenum error = get_error();
  pixel_store(GL_UNPACK_ALIGNMENT, alignment);
  entry<PFNGLBINDBUFFERPROC>(load, "glBindBuffer")(GL_PIXEL_UNPACK_BUFFER, static_cast<GLuint>(unpack_buffer));
  bind(GL_TEXTURE_2D, static_cast<GLuint>(bound));
  if (error != GL_NO_ERROR) {
    entry<PFNGLDELETETEXTURESPROC>(load, "glDeleteTextures")(1, &name_);
    throw std::runtime_error("glTexImage2D of a " + std::to_string(width) + "x" + std::to_string(height) +
                             " texture failed (GL error " + std::to_string(error) + ")");
  }
}

GlTexture::~GlTexture() {
  if (auto remove = reinterpret_cast<PFNGLDELETETEXTURESPROC>(load_("glDeleteTextures"))) remove(1, &name_);
}

}  // namespace glbudget::cli
