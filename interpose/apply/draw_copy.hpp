// Copies a texture over a framebuffer by drawing it, for contexts that have framebuffer objects
// but no glBlitFramebuffer: OpenGL ES 2.0, what Mali-400 (lima), VideoCore IV (vc4) and
// PowerVR SGX drivers give. The window's stand-in is presented and read back through it there.
// Everything the draw touches is the app's state, so each copy saves what it changes and puts
// it back: framebuffer, viewport, program, texture unit 0's 2D texture and the active unit,
// the array buffer, vertex attribute 0's array, colour mask, and the switches that would
// change the pixels (blend, depth, stencil, scissor, cull, dither, polygon offset, coverage).
#pragma once
#include <memory>

#include "gl_types.hpp"

namespace glbudget {

class DrawCopy {
 public:
  explicit DrawCopy(bool gles);
  ~DrawCopy();
  DrawCopy(const DrawCopy&) = delete;
  DrawCopy& operator=(const DrawCopy&) = delete;

  // Draws level 0 of the 2D texture `from` stretched over the whole of framebuffer `to`
  // (0: the window), `width` x `height` pixels, filtered as the texture's parameters say.
  // False where the copy program could not be built (said once).
  bool copy(GLuint from, GLuint to, int width, int height);
  // Builds the copy program on first use (a context is current); false where it cannot.
  bool ready();

 private:
  struct Gl;
  std::unique_ptr<Gl> gl_;
  bool gles_ = true;
  bool tried_ = false;
  GLuint program_ = 0, buffer_ = 0;
  GLint sampler_ = -1;
};

}  // namespace glbudget
