// Helpers for the probes that call GL directly (GL_GLEXT_PROTOTYPES before the GL headers):
// compiling a shader, a window-filling quad, and the frame loop that draws it.
#pragma once
#include <EGL/egl.h>
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdint>
#include <vector>

// A compiled shader, or 0 if it does not compile.
inline GLuint compile_shader(GLenum stage, const char* source) {
  GLuint s = glCreateShader(stage);
  glShaderSource(s, 1, &source, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  return ok ? s : 0;
}

// A window-filling quad in a fresh VAO: attribute 0, two floats per vertex.
inline void bind_fullscreen_quad(int width, int height) {
  static const float quad[] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  GLuint vao = 0, vbo = 0;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  glViewport(0, 0, width, height);
}

// `frames` frames of the bound quad with the bound program, each swapped on `surface`; returns
// the last frame's RGBA pixels, read before its swap (after a swap they are undefined).
inline std::vector<uint8_t> draw_quad_frames(int frames, int width, int height, EGLDisplay display,
                                             EGLSurface surface) {
  std::vector<uint8_t> image(static_cast<size_t>(width) * height * 4);
  for (int f = 0; f < frames; ++f) {
    glClear(GL_COLOR_BUFFER_BIT);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    if (f + 1 == frames) glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.data());
    eglSwapBuffers(display, surface);
  }
  return image;
}
