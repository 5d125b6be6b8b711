// Small GL helpers for the integration test: build programs, describe their interfaces,
// draw a full-viewport quad into an offscreen target and read it back.
#pragma once

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <cstdint>
#include <string>
#include <vector>

namespace glbudget::test {

struct CompiledShader {
  GLuint id = 0;
  bool ok = false;
  std::string log;
};
CompiledShader compile_shader(GLenum type, const std::string& source);

struct LinkedProgram {
  GLuint id = 0;
  bool ok = false;
  std::string log;
};
LinkedProgram link_program(const std::vector<GLuint>& shaders);

// Uniforms, uniform blocks, inputs, outputs, storage blocks and buffer variables with their
// types, sizes, locations and bindings, one sorted line each. Names starting with
// `skip_prefix` are left out.
std::string interface_table(GLuint program, const std::string& skip_prefix);

// Line numbers named by a Mesa info log ("0:12(5): warning: ..."), in order.
std::vector<int> logged_lines(const std::string& log);

// A square RGBA8 target with a quad (attribute "position") and a gradient texture on unit 0.
class QuadTarget {
 public:
  static constexpr int kSize = 64;  // the tests' hand counts assume 64×64 fragments
  explicit QuadTarget(int size = kSize);
  ~QuadTarget();
  QuadTarget(const QuadTarget&) = delete;
  QuadTarget& operator=(const QuadTarget&) = delete;
  std::vector<std::uint8_t> draw(GLuint program);
  void draw_without_readback(GLuint program);

 private:
  int size_;
  GLuint framebuffer_ = 0, colour_ = 0, texture_ = 0, vertex_array_ = 0, vertices_ = 0;
};

}  // namespace glbudget::test
