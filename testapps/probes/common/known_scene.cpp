#include "known_scene.hpp"

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {
struct Dialect {
  const char* vs;
  const char* fs;
  bool vao;
};

// One vertex shader and one fragment shader per dialect; B inverts the colour so
// both programs have distinct sources (and so distinct pass hashes). Not a swizzle: llvmpipe's
// linear fast path (taken when no statistics are counted) was seen ignoring `.bgra`, so the
// image would depend on whether glbudget counts.
Dialect sources(ShaderDialect d, bool pass_b) {
  switch (d) {
    case ShaderDialect::kGlsl330Core:
      return {"#version 330 core\nlayout(location=0) in vec2 pos;\nvoid main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n",
              pass_b
                  ? "#version 330 core\nuniform vec4 color;\nout vec4 frag;\nvoid main(){ frag = vec4(1.0) - color; }\n"
                  : "#version 330 core\nuniform vec4 color;\nout vec4 frag;\nvoid main(){ frag = color; }\n",
              true};
    case ShaderDialect::kGlsl120Compat:
      return {"#version 120\nattribute vec2 pos;\nvoid main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n",
              pass_b ? "#version 120\nuniform vec4 color;\nvoid main(){ gl_FragColor = vec4(1.0) - color; }\n"
                     : "#version 120\nuniform vec4 color;\nvoid main(){ gl_FragColor = color; }\n",
              false};
    case ShaderDialect::kEssl100:
      return {
          "#version 100\nattribute vec2 pos;\nvoid main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n",
          pass_b
              ? "#version 100\nprecision mediump float;\nuniform vec4 color;\nvoid main(){ gl_FragColor = vec4(1.0) - "
                "color; }\n"
              : "#version 100\nprecision mediump float;\nuniform vec4 color;\nvoid main(){ gl_FragColor = color; }\n",
          false};
    case ShaderDialect::kEssl300:
      return {"#version 300 es\nlayout(location=0) in vec2 pos;\nvoid main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n",
              pass_b ? "#version 300 es\nprecision mediump float;\nuniform vec4 color;\nout vec4 frag;\nvoid main(){ "
                       "frag = vec4(1.0) - color; }\n"
                     : "#version 300 es\nprecision mediump float;\nuniform vec4 color;\nout vec4 frag;\nvoid main(){ "
                       "frag = color; }\n",
              true};
  }
  return {};
}

// Quad A covers the left half of the window; quad B the 16x16 pixels right of and above the
// centre (in NDC for a 64x64 window; scaled to other sizes by the viewport).
const float kQuads[] = {
    -1, -1, 0,    -1, 0,    1,    -1, -1, 0,    1,    -1, 1,     // A
    0,  0,  0.5f, 0,  0.5f, 0.5f, 0,  0,  0.5f, 0.5f, 0,  0.5f,  // B
};
}  // namespace

KnownScene::KnownScene(const GlFns& gl, ShaderDialect dialect, int width, int height)
    : gl_(gl), dialect_(dialect), w_(width), h_(height) {
  prog_a_ = build_program(sources(dialect, false).vs, sources(dialect, false).fs);
  prog_b_ = build_program(sources(dialect, true).vs, sources(dialect, true).fs);
  if (!ok()) return;
  color_a_ = gl_.GetUniformLocation(prog_a_, "color");
  color_b_ = gl_.GetUniformLocation(prog_b_, "color");
  if (sources(dialect, false).vao) {
    gl_.GenVertexArrays(1, &vao_);
    gl_.BindVertexArray(vao_);
  }
  gl_.GenBuffers(1, &vbo_);
  gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);
  gl_.BufferData(GL_ARRAY_BUFFER, sizeof kQuads, kQuads, GL_STATIC_DRAW);
  gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  gl_.EnableVertexAttribArray(0);
  gl_.Viewport(0, 0, w_, h_);
}

unsigned KnownScene::build_program(const char* vs, const char* fs) {
  unsigned p = gl_.CreateProgram();
  const char* srcs[2] = {vs, fs};
  const GLenum stages[2] = {GL_VERTEX_SHADER, GL_FRAGMENT_SHADER};
  for (int i = 0; i < 2; ++i) {
    unsigned s = gl_.CreateShader(stages[i]);
    gl_.ShaderSource(s, 1, &srcs[i], nullptr);
    gl_.CompileShader(s);
    int ok = 0;
    gl_.GetShaderiv(s, GL_COMPILE_STATUS, &ok);
    if (!ok) {
      char log[1024] = {};
      gl_.GetShaderInfoLog(s, sizeof log, nullptr, log);
      error_ = std::string("shader does not compile: ") + log;
      return 0;
    }
    gl_.AttachShader(p, s);
  }
  gl_.BindAttribLocation(p, 0, "pos");
  gl_.LinkProgram(p);
  int linked = 0;
  gl_.GetProgramiv(p, GL_LINK_STATUS, &linked);
  if (!linked) error_ = "program does not link";
  return p;
}

// Colours are whole steps of 1/255. llvmpipe renders simple shaders through an 8-bit fixed-point
// path unless statistics are being counted, and the two paths may round a colour that falls
// between two 8-bit steps differently; exact steps keep the images comparable bit for bit.
static float u8(int v) { return v / 255.0f; }

void KnownScene::draw_pass_a() {
  gl_.UseProgram(prog_a_);
  gl_.Uniform4f(color_a_, u8(51), u8(102), u8(40 * (frame_ % 5)), 1);
  gl_.DrawArrays(GL_TRIANGLES, 0, 6);
  gl_.Uniform4f(color_a_, u8(230), u8(102), u8(30 * (frame_ % 7)), 1);
  gl_.DrawArrays(GL_TRIANGLES, 0, 6);
}

void KnownScene::draw_pass_b() {
  gl_.UseProgram(prog_b_);
  for (int i = 0; i < 3; ++i) {
    gl_.Uniform4f(color_b_, u8(25 * i), u8(204), u8(77), 1);
    gl_.DrawArrays(GL_TRIANGLES, 6, 6);
  }
}

void KnownScene::draw_frame(int frame) {
  frame_ = frame;
  gl_.ClearColor(u8(13), u8(13), u8(25 * (frame % 3)), 1);
  gl_.Clear(GL_COLOR_BUFFER_BIT);
  draw_pass_a();
  draw_pass_b();
}

std::vector<uint8_t> KnownScene::read_rgba() {
  std::vector<uint8_t> px(static_cast<size_t>(w_) * h_ * 4);
  gl_.Finish();
  gl_.ReadPixels(0, 0, w_, h_, GL_RGBA, GL_UNSIGNED_BYTE, px.data());
  return px;
}

bool write_ppm(const std::string& path, const std::vector<uint8_t>& rgba, int width, int height) {
  if (path.empty()) return true;
  FILE* f = fopen(path.c_str(), "wb");
  if (!f) return false;
  fprintf(f, "P6\n%d %d\n255\n", width, height);
  for (size_t i = 0; i + 3 < rgba.size(); i += 4) fwrite(&rgba[i], 1, 3, f);
  return fclose(f) == 0;
}

ProbeArgs parse_probe_args(int argc, char** argv) {
  ProbeArgs a;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--frames"))
      a.frames = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--out"))
      a.out = argv[i + 1];
    else if (!strcmp(argv[i], "--size"))
      a.width = a.height = atoi(argv[i + 1]);
  }
  return a;
}
