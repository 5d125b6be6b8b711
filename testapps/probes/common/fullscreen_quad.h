// A window-filling quad in a fresh VAO, for the probes that call GL directly
// (GL_GLEXT_PROTOTYPES before the GL headers): attribute 0, two floats per vertex.
#pragma once
#include <GL/gl.h>
#include <GL/glext.h>

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
