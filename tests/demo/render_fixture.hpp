// Shared by the GL tests: one EGL surfaceless context per test program, and a pass observer
// that counts each pass's work with pipeline-statistics queries.
#pragma once
#include <GL/glew.h>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "context.hpp"
#include "renderer.hpp"

namespace demo_test {

inline constexpr int kWidth = 128, kHeight = 72;

// Created on first use, current for the rest of the program.
demo::GlContext& gl_context();

struct PassWork {
  bool ran = false;
  uint64_t fragments = 0;  // fragment shader invocations
  uint64_t vertices = 0;   // vertex shader invocations
  GLuint program = 0;      // program bound when the pass ended
};

class PassCounters : public demo::PassObserver {
 public:
  PassCounters();
  ~PassCounters() override;
  void pass_begin(demo::Pass pass) override;
  void pass_end(demo::Pass pass) override;
  // Waits for the queries of the last frame.
  std::array<PassWork, demo::kPassCount> collect();

 private:
  std::array<GLuint, demo::kPassCount> fragment_queries_{}, vertex_queries_{};
  std::array<PassWork, demo::kPassCount> work_{};
};

struct RenderedFrame {
  std::vector<uint8_t> pixels;  // RGB8
  demo::FrameDraws draws;
  std::array<PassWork, demo::kPassCount> work;
  const PassWork& operator[](demo::Pass pass) const { return work[static_cast<int>(pass)]; }
};

RenderedFrame render(demo::Renderer& renderer, const demo::Config& config, double time);

// The full source of the fragment shader of `program` (all strings as the driver sees them).
std::string fragment_source(GLuint program);
// Mean absolute difference per channel between two images, 0..255.
double mean_difference(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b);

}  // namespace demo_test
