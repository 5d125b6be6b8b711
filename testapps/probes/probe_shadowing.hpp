// What the program-shadowing probes (issue 12: probe_uniforms, probe_subroutines,
// probe_samplers, probe_blocks, probe_attributes, probe_pipeline_stages, probe_relink,
// probe_locations, probe_bad_variant; tests/interpose/shadowing_test.cpp runs them) share. They know nothing of
// glbudget: each draws full-window quads whose shader writes what it received (uniform values, sampled texels, block
// contents) into a render target, reads it back after every draw and compares it with what the app set; a mismatch is
// printed on stderr
// ("<probe>: frame F draw D: what: expected X, got Y") and makes the exit code 1. Every draw also
// prints a line on stdout, "frame F draw D mark M ...", where M is what the shader's
// VARIANT_MARK macro says (0 in the app's own source): the tests tell which program drew from it.
//
// Include after `#define GL_GLEXT_PROTOTYPES 1`.
#pragma once
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "common/direct_gl.hpp"
#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

namespace shadow_probe {

class Probe {
 public:
  explicit Probe(const char* name) : name_(name) {}
  const char* name() const { return name_; }

  // One mismatch: printed (the first 60), counted.
  void fail(const char* format, ...) __attribute__((format(printf, 2, 3))) {
    ++failures_;
    if (failures_ > 60) return;
    std::va_list ap;
    va_start(ap, format);
    std::fprintf(stderr, "%s: frame %d draw %d: ", name_, frame_, draw_);
    std::vfprintf(stderr, format, ap);
    std::fputc('\n', stderr);
    va_end(ap);
  }
  // The app itself raised no GL error since the last check (the shim must raise none).
  void check_gl_error(const char* where) {
    for (GLenum e = glGetError(), n = 0; e != GL_NO_ERROR && n < 8; e = glGetError(), ++n)
      fail("glGetError() = 0x%04x %s", e, where);
  }
  void set_frame(int frame) {
    frame_ = frame;
    draw_ = 0;
  }
  int frame() const { return frame_; }
  int draw() const { return draw_; }
  void next_draw() { ++draw_; }
  // Exit code: 0 when nothing differed.
  int finish() {
    check_gl_error("at exit");
    if (failures_ > 60) std::fprintf(stderr, "%s: ... %d mismatches in all\n", name_, failures_);
    std::fflush(stdout);
    return failures_ ? 1 : 0;
  }
  int failures() const { return failures_; }

 private:
  const char* name_;
  int failures_ = 0;
  int frame_ = 0, draw_ = 0;
};

struct Stage {
  GLenum stage;
  std::string source;
};

// A compiled shader, or 0 with the driver's log on stderr.
inline GLuint compile_or_say(const char* probe, GLenum stage, const std::string& source) {
  GLuint s = glCreateShader(stage);
  const char* text = source.c_str();
  glShaderSource(s, 1, &text, nullptr);
  glCompileShader(s);
  GLint ok = 0;
  glGetShaderiv(s, GL_COMPILE_STATUS, &ok);
  if (ok) return s;
  char log[2048] = {};
  glGetShaderInfoLog(s, sizeof log, nullptr, log);
  std::fprintf(stderr, "%s: shader does not compile: %s\n", probe, log);
  glDeleteShader(s);
  return 0;
}

inline bool linked_or_say(const char* probe, GLuint program) {
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (linked) return true;
  char log[2048] = {};
  glGetProgramInfoLog(program, sizeof log, nullptr, log);
  std::fprintf(stderr, "%s: program does not link: %s\n", probe, log);
  return false;
}

// A linked program of `stages`; `before_link` runs between attaching and linking (locations).
// 0 on failure, with the reason on stderr. The shaders stay attached (so a relink can reuse them).
inline GLuint build_program(const char* probe, const std::vector<Stage>& stages,
                            const std::function<void(GLuint)>& before_link = {},
                            std::vector<GLuint>* shaders = nullptr) {
  GLuint program = glCreateProgram();
  for (const Stage& st : stages) {
    GLuint s = compile_or_say(probe, st.stage, st.source);
    if (!s) return 0;
    glAttachShader(program, s);
    if (shaders) shaders->push_back(s);
  }
  if (before_link) before_link(program);
  glLinkProgram(program);
  return linked_or_say(probe, program) ? program : 0;
}

// The vertex stage most probes share: a full-window quad from attribute 0 (bind_fullscreen_quad).
inline const char* quad_vertex_shader() {
  return "#version 450 core\n"
         "layout(location = 0) in vec2 pos;\n"
         "void main() { gl_Position = vec4(pos, 0.0, 1.0); }\n";
}

// A W x H GL_RGBA32UI render target: one "slot" of four 32-bit words per pixel, exact whatever
// the values (no normalisation, no 8-bit fast path), slot = y * W + x.
class SlotTarget {
 public:
  bool create(int width, int height) {
    w_ = width;
    h_ = height;
    glGenTextures(1, &tex_);
    glBindTexture(GL_TEXTURE_2D, tex_);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32UI, w_, h_);
    glGenFramebuffers(1, &fbo_);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, tex_, 0);
    return glCheckFramebufferStatus(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
  }
  void bind() const {
    glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
    glViewport(0, 0, w_, h_);
  }
  // Clears to 0xdead0000 + slot-independent filler, draws the bound quad, reads the slots back.
  std::vector<uint32_t> draw_and_read() const {
    bind();
    const GLuint filler[4] = {0xdead0000u, 0xdead0001u, 0xdead0002u, 0xdead0003u};
    glClearBufferuiv(GL_COLOR, 0, filler);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    std::vector<uint32_t> words(static_cast<size_t>(w_) * h_ * 4);
    glReadPixels(0, 0, w_, h_, GL_RGBA_INTEGER, GL_UNSIGNED_INT, words.data());
    return words;
  }
  int slots() const { return w_ * h_; }
  int width() const { return w_; }

 private:
  int w_ = 0, h_ = 0;
  GLuint tex_ = 0, fbo_ = 0;
};

// GLSL: `uvec4 enc(x)` for every scalar and vector type of float, int, uint, bool (each
// component's bits, zero padded) and double, dvec2 (unpackDouble2x32 of each component).
inline const char* glsl_encoders(bool doubles) {
  static const char* const kBase =
      "uvec4 enc(float x) { return uvec4(floatBitsToUint(x), 0u, 0u, 0u); }\n"
      "uvec4 enc(vec2 x) { return uvec4(floatBitsToUint(x), 0u, 0u); }\n"
      "uvec4 enc(vec3 x) { return uvec4(floatBitsToUint(x), 0u); }\n"
      "uvec4 enc(vec4 x) { return floatBitsToUint(x); }\n"
      "uvec4 enc(int x) { return uvec4(uint(x), 0u, 0u, 0u); }\n"
      "uvec4 enc(ivec2 x) { return uvec4(uvec2(x), 0u, 0u); }\n"
      "uvec4 enc(ivec3 x) { return uvec4(uvec3(x), 0u); }\n"
      "uvec4 enc(ivec4 x) { return uvec4(x); }\n"
      "uvec4 enc(uint x) { return uvec4(x, 0u, 0u, 0u); }\n"
      "uvec4 enc(uvec2 x) { return uvec4(x, 0u, 0u); }\n"
      "uvec4 enc(uvec3 x) { return uvec4(x, 0u); }\n"
      "uvec4 enc(uvec4 x) { return x; }\n"
      "uvec4 enc(bool x) { return uvec4(x ? 1u : 0u, 0u, 0u, 0u); }\n"
      "uvec4 enc(bvec2 x) { return uvec4(uvec2(x), 0u, 0u); }\n"
      "uvec4 enc(bvec3 x) { return uvec4(uvec3(x), 0u); }\n"
      "uvec4 enc(bvec4 x) { return uvec4(x); }\n";
  static const std::string kWithDoubles =
      std::string(kBase) +
      "uvec4 enc(double x) { return uvec4(unpackDouble2x32(x), 0u, 0u); }\n"
      "uvec4 enc(dvec2 x) { return uvec4(unpackDouble2x32(x.x), unpackDouble2x32(x.y)); }\n";
  return doubles ? kWithDoubles.c_str() : kBase;
}

// GLSL: `uvec4 slot(int i)` returning cases[i] (0xffffffff past the end). Switches of at
// most 32 cases inside one on i / 32: llvmpipe was seen never taking the cases past the 78th
// of one long switch.
inline std::string glsl_slot_function(const std::vector<std::string>& cases) {
  std::string s;
  const size_t groups = (cases.size() + 31) / 32;
  for (size_t g = 0; g < groups; ++g) {
    s += "uvec4 slot" + std::to_string(g) + "(int i) {\n  switch (i) {\n";
    for (size_t i = g * 32; i < cases.size() && i < g * 32 + 32; ++i)
      s += "    case " + std::to_string(i % 32) + ": return " + cases[i] + ";\n";
    s += "  }\n  return uvec4(0xffffffffu);\n}\n";
  }
  s += "uvec4 slot(int i) {\n  switch (i / 32) {\n";
  for (size_t g = 0; g < groups; ++g)
    s += "    case " + std::to_string(g) + ": return slot" + std::to_string(g) + "(i % 32);\n";
  s += "  }\n  return uvec4(0xffffffffu);\n}\n";
  return s;
}

inline uint32_t float_bits(float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  return u;
}

inline void double_words(double d, uint32_t* lo, uint32_t* hi) {
  uint64_t u;
  std::memcpy(&u, &d, 8);
  *lo = static_cast<uint32_t>(u);
  *hi = static_cast<uint32_t>(u >> 32);
}

// Compares one slot's four words; `what` names it in the message.
inline void expect_slot(Probe& probe, const std::vector<uint32_t>& words, int slot, const uint32_t expected[4],
                        const std::string& what) {
  const uint32_t* got = &words[static_cast<size_t>(slot) * 4];
  if (std::memcmp(got, expected, 16) == 0) return;
  probe.fail("%s (slot %d): expected %08x %08x %08x %08x, got %08x %08x %08x %08x", what.c_str(), slot, expected[0],
             expected[1], expected[2], expected[3], got[0], got[1], got[2], got[3]);
}

// Slot 0 of every probe: (VARIANT_MARK, 0x600d, 0, 0); prints the draw's line, returns the mark.
inline uint32_t report_mark(Probe& probe, const std::vector<uint32_t>& words, const std::string& extra = {}) {
  if (words[1] != 0x600du) probe.fail("slot 0 is not the mark slot: %08x %08x", words[0], words[1]);
  std::printf("frame %d draw %d mark %u%s%s\n", probe.frame(), probe.draw(), words[0], extra.empty() ? "" : " ",
              extra.c_str());
  return words[0];
}

// The end of a frame: the window bound again and swapped (the switch of configuration happens
// at the swap).
inline void swap_window(EglWindow& w) {
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  eglSwapBuffers(w.display, w.surface);
}

// The probe's verdict, after releasing its context and display.
inline int finish_and_close(Probe& probe, EglWindow& w) {
  const int code = probe.finish();
  eglMakeCurrent(w.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(w.display, w.context);
  eglTerminate(w.display);
  return code;
}

}  // namespace shadow_probe
