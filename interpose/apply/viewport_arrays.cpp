// Viewport arrays (GL 4.1, ARB_viewport_array): glViewportIndexedf(v), glViewportArrayv,
// glScissorIndexed(v), glScissorArrayv and their glGet*i_v queries, scaled and answered as
// glViewport and glScissor are. Wine's wined3d sets every viewport and scissor box this way
// where the driver has viewport arrays, so Windows games under Wine's GL renderer draw through
// here.
#include <cmath>

#include "apply_gl.hpp"
#include "render_targets.hpp"

namespace glbudget {

namespace {
// A float box scaled by its edges, rounded as scale_box rounds glViewport's.
std::array<GLfloat, 4> scaled_box(const std::array<GLfloat, 4>& in, double sx, double sy) {
  const double x0 = std::round(in[0] * sx), y0 = std::round(in[1] * sy);
  return {static_cast<GLfloat>(x0), static_cast<GLfloat>(y0),
          static_cast<GLfloat>(std::round((in[0] + in[2]) * sx) - x0),
          static_cast<GLfloat>(std::round((in[1] + in[3]) * sy) - y0)};
}
}  // namespace

bool TargetScaler::start_indexed_boxes() {
  if (!viewports_.empty()) return true;
  const ApplyGl& g = agl();
  if (!g.ViewportIndexedf || !g.ScissorIndexed) return false;
  GLint count = 0;
  g.GetIntegerv(GL_MAX_VIEWPORTS, &count);
  if (count <= 0) return false;
  // Until now every index held index 0's box: glViewport and glScissor set them all.
  viewports_.assign(static_cast<size_t>(count), float_box(viewport_));
  scissors_.assign(static_cast<size_t>(count), scissor_);
  return true;
}

void TargetScaler::apply_indexed_boxes(double sx, double sy) {
  const ApplyGl& g = agl();
  for (size_t i = 0; i < viewports_.size(); ++i) {
    const auto v = scaled_box(viewports_[i], sx, sy);
    g.ViewportIndexedf(static_cast<GLuint>(i), v[0], v[1], v[2], v[3]);
    GLint b[4];
    scale_box(scissors_[i].data(), sx, sy, b);
    g.ScissorIndexed(static_cast<GLuint>(i), b[0], b[1], b[2], b[3]);
  }
}

bool TargetScaler::viewport_indexed(GLuint index, const GLfloat* box) {
  if (!box || box[2] < 0 || box[3] < 0 || !start_indexed_boxes() || index >= viewports_.size()) return false;
  viewports_[index] = {box[0], box[1], box[2], box[3]};
  if (index == 0)
    for (size_t i = 0; i < 4; ++i) viewport_[i] = static_cast<GLint>(std::lround(box[i]));
  double sx, sy;
  scale_of(draw_fbo_, &sx, &sy);
  const auto v = scaled_box(viewports_[index], sx, sy);
  agl().ViewportIndexedf(index, v[0], v[1], v[2], v[3]);
  return true;
}

bool TargetScaler::scissor_indexed(GLuint index, const GLint* box) {
  if (!box || box[2] < 0 || box[3] < 0 || !start_indexed_boxes() || index >= scissors_.size()) return false;
  scissors_[index] = {box[0], box[1], box[2], box[3]};
  if (index == 0) scissor_ = scissors_[0];
  double sx, sy;
  scale_of(draw_fbo_, &sx, &sy);
  GLint b[4];
  scale_box(box, sx, sy, b);
  agl().ScissorIndexed(index, b[0], b[1], b[2], b[3]);
  return true;
}

bool TargetScaler::app_viewport_at(GLuint index, GLfloat* box) const {
  if (!box || !boxes_scaled()) return false;
  if (!viewports_.empty() && index >= viewports_.size()) return false;
  // Before any box is set by index, every index holds index 0's.
  const std::array<GLfloat, 4> b = viewports_.empty() ? float_box(viewport_) : viewports_[index];
  for (size_t i = 0; i < 4; ++i) box[i] = b[i];
  return true;
}

bool TargetScaler::app_scissor_at(GLuint index, GLint* box) const {
  if (!box || !boxes_scaled()) return false;
  const std::array<GLint, 4>* b = &scissor_;
  if (!scissors_.empty()) {
    if (index >= scissors_.size()) return false;
    b = &scissors_[index];
  }
  for (size_t i = 0; i < 4; ++i) box[i] = (*b)[i];
  return true;
}

}  // namespace glbudget
