#include "render_fixture.hpp"

#include <cstdlib>
#include <memory>
#include <stdexcept>

namespace demo_test {

demo::GlContext& gl_context() {
  static const std::unique_ptr<demo::GlContext> context = [] {
    auto created = demo::create_egl_context(kWidth, kHeight);
    if (!GLEW_ARB_pipeline_statistics_query) throw std::runtime_error("GL_ARB_pipeline_statistics_query missing");
    return created;
  }();
  return *context;
}

PassCounters::PassCounters() {
  glGenQueries(demo::kPassCount, fragment_queries_.data());
  glGenQueries(demo::kPassCount, vertex_queries_.data());
}

PassCounters::~PassCounters() {
  glDeleteQueries(demo::kPassCount, fragment_queries_.data());
  glDeleteQueries(demo::kPassCount, vertex_queries_.data());
}

void PassCounters::pass_begin(demo::Pass pass) {
  const int i = static_cast<int>(pass);
  work_[i] = PassWork{true, 0, 0, 0};
  glBeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, fragment_queries_[i]);
  glBeginQuery(GL_VERTEX_SHADER_INVOCATIONS_ARB, vertex_queries_[i]);
}

void PassCounters::pass_end(demo::Pass pass) {
  const int i = static_cast<int>(pass);
  glEndQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
  glEndQuery(GL_VERTEX_SHADER_INVOCATIONS_ARB);
  GLint program = 0;
  glGetIntegerv(GL_CURRENT_PROGRAM, &program);
  work_[i].program = static_cast<GLuint>(program);
}

std::array<PassWork, demo::kPassCount> PassCounters::collect() {
  for (int i = 0; i < demo::kPassCount; ++i) {
    if (!work_[i].ran) continue;
    GLuint64 value = 0;
    glGetQueryObjectui64v(fragment_queries_[i], GL_QUERY_RESULT, &value);
    work_[i].fragments = value;
    glGetQueryObjectui64v(vertex_queries_[i], GL_QUERY_RESULT, &value);
    work_[i].vertices = value;
  }
  auto result = work_;
  work_ = {};
  return result;
}

RenderedFrame render(demo::Renderer& renderer, const demo::Config& config, double time) {
  PassCounters counters;
  RenderedFrame frame;
  frame.draws = renderer.render(config, time, &counters);
  frame.pixels = renderer.read_pixels();
  frame.work = counters.collect();
  return frame;
}

std::string fragment_source(GLuint program) {
  GLuint shaders[4] = {};
  GLsizei count = 0;
  glGetAttachedShaders(program, 4, &count, shaders);
  for (GLsizei i = 0; i < count; ++i) {
    GLint type = 0, length = 0;
    glGetShaderiv(shaders[i], GL_SHADER_TYPE, &type);
    if (type != GL_FRAGMENT_SHADER) continue;
    glGetShaderiv(shaders[i], GL_SHADER_SOURCE_LENGTH, &length);
    std::string source(static_cast<size_t>(length), '\0');
    glGetShaderSource(shaders[i], length, nullptr, source.data());
    return source;
  }
  return {};
}

double mean_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b) {
  if (a.size() != b.size() || a.empty()) return 255.0;
  uint64_t sum = 0;
  for (size_t i = 0; i < a.size(); ++i) sum += static_cast<uint64_t>(std::abs(int{a[i]} - int{b[i]}));
  return static_cast<double>(sum) / static_cast<double>(a.size());
}

}  // namespace demo_test
