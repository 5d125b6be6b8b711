// Draws the one-triangle full-screen pass of fullscreen.vert (core profile needs a VAO).
#pragma once
#include <GL/glew.h>

namespace demo {

class FullscreenTriangle {
 public:
  FullscreenTriangle() { glGenVertexArrays(1, &vao_); }
  ~FullscreenTriangle() { glDeleteVertexArrays(1, &vao_); }
  FullscreenTriangle(const FullscreenTriangle&) = delete;
  FullscreenTriangle& operator=(const FullscreenTriangle&) = delete;

  // Draws with depth testing off; returns the number of draw calls (1).
  int draw() const {
    glDisable(GL_DEPTH_TEST);
    glBindVertexArray(vao_);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glBindVertexArray(0);
    return 1;
  }

 private:
  GLuint vao_ = 0;
};

// Binds `texture` to texture unit `unit` and points `sampler` of the current program at it.
inline void bind_texture(GLint sampler, int unit, GLuint texture) {
  glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
  glBindTexture(GL_TEXTURE_2D, texture);
  glUniform1i(sampler, unit);
}

}  // namespace demo
