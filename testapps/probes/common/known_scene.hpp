// The probes' known geometry: per frame, pass A draws a half-window quad twice and pass B a
// 16x16-pixel quad three times, so batches, vertices, fragments and primitives are exact:
//   pass A: 2 batches, 12 vertices, 2 * (W/2 * H) fragments, 4 primitives
//   pass B: 3 batches, 18 vertices, 3 * 256 fragments, 6 primitives
// (W, H even and >= 32; no depth test, no blending, so every covered pixel shades once.)
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "gl_fns.hpp"

enum class ShaderDialect { kGlsl330Core, kGlsl120Compat, kEssl100, kEssl300 };

class KnownScene {
 public:
  KnownScene(const GlFns& gl, ShaderDialect dialect, int width, int height);
  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }
  void draw_pass_a();          // program A, 2 draws
  void draw_pass_b();          // program B, 3 draws
  void draw_frame(int frame);  // clear, pass A, pass B (colours vary with the frame)
  std::vector<uint8_t> read_rgba();
  const GlFns& gl() const { return gl_; }

 private:
  unsigned build_program(const char* vs, const char* fs);
  const GlFns& gl_;
  ShaderDialect dialect_;
  int w_, h_;
  unsigned prog_a_ = 0, prog_b_ = 0, vbo_ = 0, vao_ = 0;
  int color_a_ = -1, color_b_ = -1;
  int frame_ = 0;
  std::string error_;
};

// Writes the pixels as a binary PPM (RGB); returns false on I/O failure.
bool write_ppm(const std::string& path, const std::vector<uint8_t>& rgba, int width, int height);

// Command-line helpers shared by the probes: --frames N, --out PATH.
struct ProbeArgs {
  int frames = 5;
  std::string out;
  int width = 64, height = 64;
};
ProbeArgs parse_probe_args(int argc, char** argv);
