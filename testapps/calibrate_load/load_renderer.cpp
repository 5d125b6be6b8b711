#include "load_renderer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace calibrate_load {
namespace {

// The first quad_vertices vertices are full-screen layers (two triangles each, the last one
// last_layer of the height); every other vertex sits at one point off the screen: degenerate
// triangles that cost vertex work and are clipped before any fragment. (At the screen's centre
// instead, llvmpipe 22.3 drew nothing at all of a 9-vertex draw: one layer and one triangle.)
constexpr const char* kVertexShader = R"(#version 330 core
uniform int quad_vertices;
uniform float last_layer;
void main() {
  if (gl_VertexID < quad_vertices) {
    int corner = gl_VertexID % 6;  // two triangles: (0,0) (1,0) (0,1), (0,1) (1,0) (1,1)
    vec2 c = vec2(corner == 1 || corner == 4 || corner == 5 ? 1.0 : 0.0,
                  corner == 2 || corner == 3 || corner == 5 ? 1.0 : 0.0);
    if (gl_VertexID / 6 == quad_vertices / 6 - 1) c.y *= last_layer;
    gl_Position = vec4(c * 2.0 - 1.0, 0.0, 1.0);
  } else {
    gl_Position = vec4(2.0, 2.0, 0.0, 1.0);
  }
}
)";

constexpr const char* kFragmentShader = R"(#version 330 core
out vec4 color;
void main() { color = vec4(1.0 / 255.0); }
)";

GLuint compile(GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    char log[1024] = {};
    glGetShaderInfoLog(shader, sizeof log, nullptr, log);
    glDeleteShader(shader);
    throw std::runtime_error(std::string("shader compile failed: ") + log);
  }
  return shader;
}

}  // namespace

LoadRenderer::LoadRenderer(const LoadShape& shape, int width, int height)
    : screen_fragments_(static_cast<double>(width) * height) {
  set_shape(shape);
  const GLuint vs = compile(GL_VERTEX_SHADER, kVertexShader);
  const GLuint fs = compile(GL_FRAGMENT_SHADER, kFragmentShader);
  program_ = glCreateProgram();
  glAttachShader(program_, vs);
  glAttachShader(program_, fs);
  glLinkProgram(program_);
  glDeleteShader(vs);
  glDeleteShader(fs);
  GLint ok = GL_FALSE;
  glGetProgramiv(program_, GL_LINK_STATUS, &ok);
  if (!ok) throw std::runtime_error("program link failed");
  quad_vertices_location_ = glGetUniformLocation(program_, "quad_vertices");
  last_layer_location_ = glGetUniformLocation(program_, "last_layer");
  glGenVertexArrays(1, &vertex_array_);
  glViewport(0, 0, width, height);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  // Additive blending: a renderer that drops fragments hidden under an opaque layer (llvmpipe
  // does, per tile) must still shade every layer.
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_ONE);
  glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
}

void LoadRenderer::set_shape(const LoadShape& shape) {
  shape_ = shape;
  batch_vertices_ = static_cast<GLsizei>(std::max<std::int64_t>(3, (shape.vertices + 2) / 3 * 3));
  quad_vertices_ = 0;
  last_layer_ = 1.0f;
  if (shape.fragments > 0) {
    const double layers = std::ceil(static_cast<double>(shape.fragments) / screen_fragments_);
    quad_vertices_ = static_cast<GLint>(6 * layers);
    last_layer_ = static_cast<GLfloat>(static_cast<double>(shape.fragments) / screen_fragments_ - (layers - 1.0));
  }
}

LoadRenderer::~LoadRenderer() {
  glDeleteVertexArrays(1, &vertex_array_);
  glDeleteProgram(program_);
}

void LoadRenderer::draw_frame() {
  glClear(GL_COLOR_BUFFER_BIT);
  if (shape_.batches == 0) return;
  glUseProgram(program_);
  glBindVertexArray(vertex_array_);
  glUniform1f(last_layer_location_, last_layer_);
  glUniform1i(quad_vertices_location_, quad_vertices_);
  glDrawArrays(GL_TRIANGLES, 0, quad_vertices_ + batch_vertices_);
  if (shape_.batches > 1) glUniform1i(quad_vertices_location_, 0);
  for (std::int64_t i = 1; i < shape_.batches; ++i) glDrawArrays(GL_TRIANGLES, 0, batch_vertices_);
}

}  // namespace calibrate_load
