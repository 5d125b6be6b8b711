// Draws the calibration load. Attribute-less: positions come from gl_VertexID, so no buffer
// grows with the counts and the shaders stay trivial: the counts, not the shaders, set the cost.
#pragma once
#include <GL/glew.h>

#include <cstdint>

namespace calibrate_load {

struct LoadShape {
  std::int64_t batches = 1;
  std::int64_t vertices = 3;  // per batch
  std::int64_t fragments = 0;
};

class LoadRenderer {
 public:
  LoadRenderer(const LoadShape& shape, int width, int height);  // throws std::runtime_error
  ~LoadRenderer();
  LoadRenderer(const LoadRenderer&) = delete;
  LoadRenderer& operator=(const LoadRenderer&) = delete;

  void set_shape(const LoadShape& shape);  // only uniforms change: no recompile between steps
  void draw_frame();

 private:
  LoadShape shape_;
  double screen_fragments_ = 0.0;
  GLsizei batch_vertices_ = 3;  // whole triangles
  GLint quad_vertices_ = 0;     // six per full-screen layer
  GLfloat last_layer_ = 1.0f;   // the last layer's share of the screen's height
  GLuint program_ = 0;
  GLuint vertex_array_ = 0;
  GLint quad_vertices_location_ = -1;
  GLint last_layer_location_ = -1;
};

}  // namespace calibrate_load
