// Sampler uniforms and uniforms a manifest level holds (issue 12, shadowing case 2). Ten 1x1
// textures, one per unit: units 0-5 GL_RGBA32F (texel unit*10 + 1..4), 6-7 GL_RGBA32UI, 8-9
// GL_RGBA32I, so a texel fetched names the unit a sampler points at. Every frame the app points
// its samplers at other units with glUniform1i / glUniform1iv (whole array and element by
// element at `loc + i`) and sets u_x, u_hv, u_xa and u_free, as apps set per-frame values.
//
// Checked here, whatever the level: s_a, s_u, s_i, s_arr[3], s_bound (layout(binding = 5), never
// set) and u_free. Printed, for the test to compare with the levels it forced (a manifest
// level may hold them): "frame F draw D mark M phase P u_x X u_hv X,Y,Z u_xa A,B s_b UNIT",
// where the app set, in phase P: u_x = 100.5 + P, u_hv = (P, P + 0.5, P + 0.25),
// u_xa = (10 + P, 20 + P), s_b to unit (P + 1) % 6.
// Each frame: a draw that must show the previous frame's values (set before the swap), new
// values (glUniform* in even frames, glProgramUniform* in odd ones), a draw that must show them.
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

const char* const kFragment =
    "#version 450 core\n"
    "// PROBE_SAMPLERS\n"
    "#define VARIANT_MARK 0\n"
    "#if VARIANT_MARK\n"
    "uniform sampler2D a_extra;\n"
    "uniform vec4 a_pad[2];\n"
    "#define MARK_SHIFT uint(texelFetch(a_extra, ivec2(0), 0).x + a_pad[1].w > 1e30)\n"
    "#else\n"
    "#define MARK_SHIFT 0u\n"
    "#endif\n"
    "uniform sampler2D s_a;\n"
    "uniform sampler2D s_b;\n"
    "uniform usampler2D s_u;\n"
    "uniform isampler2D s_i;\n"
    "uniform sampler2D s_arr[3];\n"
    "layout(binding = 5) uniform sampler2D s_bound;\n"
    "uniform float u_x;\n"
    "uniform vec3 u_hv;\n"
    "uniform float u_xa[2];\n"
    "uniform int u_free;\n"
    "out uvec4 o;\n"
    "uvec4 f(vec4 v) { return floatBitsToUint(v); }\n"
    "uvec4 slot(int i) {\n"
    "  switch (i) {\n"
    "    case 0: return uvec4(uint(VARIANT_MARK) + MARK_SHIFT, 0x600du, 0u, 0u);\n"
    "    case 1: return f(texelFetch(s_a, ivec2(0), 0));\n"
    "    case 2: return f(texelFetch(s_b, ivec2(0), 0));\n"
    "    case 3: return texelFetch(s_u, ivec2(0), 0);\n"
    "    case 4: return uvec4(texelFetch(s_i, ivec2(0), 0));\n"
    "    case 5: return f(texelFetch(s_arr[0], ivec2(0), 0));\n"
    "    case 6: return f(texelFetch(s_arr[1], ivec2(0), 0));\n"
    "    case 7: return f(texelFetch(s_arr[2], ivec2(0), 0));\n"
    "    case 8: return f(texelFetch(s_bound, ivec2(0), 0));\n"
    "    case 9: return uvec4(floatBitsToUint(u_x), 0u, 0u, 0u);\n"
    "    case 10: return uvec4(floatBitsToUint(u_hv), 0u);\n"
    "    case 11: return uvec4(floatBitsToUint(u_xa[0]), floatBitsToUint(u_xa[1]), 0u, 0u);\n"
    "    case 12: return uvec4(uint(u_free), 0u, 0u, 0u);\n"
    "  }\n"
    "  return uvec4(0xffffffffu);\n"
    "}\n"
    "void main() { ivec2 p = ivec2(gl_FragCoord.xy); o = slot(p.y * 4 + p.x); }\n";

constexpr int kUnits = 10;

// The texel of the texture on `unit`, as the shader's slot shows it.
void texel_words(int unit, uint32_t out[4]) {
  for (int c = 0; c < 4; ++c) {
    if (unit < 6)
      out[c] = float_bits(static_cast<float>(unit * 10 + c + 1));
    else if (unit < 8)
      out[c] = 0x80000000u + static_cast<uint32_t>(unit * 16 + c);
    else
      out[c] = static_cast<uint32_t>(-(unit * 100 + c + 1));
  }
}

GLuint make_texture(int unit) {
  GLuint tex = 0;
  glGenTextures(1, &tex);
  glActiveTexture(GL_TEXTURE0 + static_cast<GLenum>(unit));
  glBindTexture(GL_TEXTURE_2D, tex);
  uint32_t words[4];
  texel_words(unit, words);
  if (unit < 6)
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32F, 1, 1, 0, GL_RGBA, GL_FLOAT, words);
  else if (unit < 8)
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32UI, 1, 1, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, words);
  else
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA32I, 1, 1, 0, GL_RGBA_INTEGER, GL_INT, words);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return tex;
}

// The units the app points its samplers at in phase p.
struct Units {
  int a, b, u, i, arr[3];
};
Units units(int p) { return {p % 6, (p + 1) % 6, 6 + p % 2, 8 + p % 2, {(p + 2) % 6, (p + 3) % 6, (p + 4) % 6}}; }

float as_float(uint32_t u) {
  float f;
  std::memcpy(&f, &u, 4);
  return f;
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_samplers");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, 4, 4, &w)) return 2;
  const GLuint prog =
      build_program(probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, kFragment}});
  if (!prog) return 2;
  SlotTarget target;  // before the textures: it binds its own on the active unit
  if (!target.create(4, 4)) return 2;
  for (int unit = 0; unit < kUnits; ++unit) make_texture(unit);
  glActiveTexture(GL_TEXTURE0);
  const GLint l_a = glGetUniformLocation(prog, "s_a"), l_b = glGetUniformLocation(prog, "s_b");
  const GLint l_u = glGetUniformLocation(prog, "s_u"), l_i = glGetUniformLocation(prog, "s_i");
  const GLint l_arr = glGetUniformLocation(prog, "s_arr");
  const GLint l_x = glGetUniformLocation(prog, "u_x"), l_hv = glGetUniformLocation(prog, "u_hv");
  const GLint l_xa = glGetUniformLocation(prog, "u_xa"), l_free = glGetUniformLocation(prog, "u_free");
  if (l_a < 0 || l_b < 0 || l_u < 0 || l_i < 0 || l_arr < 0 || l_x < 0 || l_hv < 0 || l_xa < 0 || l_free < 0) {
    std::fprintf(stderr, "probe_samplers: a uniform has no location\n");
    return 2;
  }
  bind_fullscreen_quad(4, 4);
  probe.check_gl_error("after setup");

  auto draw_and_check = [&](int p) {
    const std::vector<uint32_t> words = target.draw_and_read();
    const Units u = units(p);
    uint32_t expected[4];
    texel_words(u.a, expected);
    expect_slot(probe, words, 1, expected, "s_a");
    texel_words(u.u, expected);
    expect_slot(probe, words, 3, expected, "s_u");
    texel_words(u.i, expected);
    expect_slot(probe, words, 4, expected, "s_i");
    for (int k = 0; k < 3; ++k) {
      texel_words(u.arr[k], expected);
      expect_slot(probe, words, 5 + k, expected, "s_arr[" + std::to_string(k) + "]");
    }
    texel_words(5, expected);
    expect_slot(probe, words, 8, expected, "s_bound (layout(binding = 5))");
    const uint32_t free_words[4] = {static_cast<uint32_t>(p * 3 + 1), 0, 0, 0};
    expect_slot(probe, words, 12, free_words, "u_free");
    // s_b's unit, from its texel (float units only); -1 if it names none.
    const float b = as_float(words[2 * 4]);
    const int b_unit = (b >= 1 && b <= 51 && static_cast<int>(b - 1) % 10 == 0) ? static_cast<int>(b - 1) / 10 : -1;
    char extra[256];
    std::snprintf(extra, sizeof extra, "phase %d u_x %.9g u_hv %.9g,%.9g,%.9g u_xa %.9g,%.9g s_b %d", p,
                  as_float(words[9 * 4]), as_float(words[10 * 4]), as_float(words[10 * 4 + 1]),
                  as_float(words[10 * 4 + 2]), as_float(words[11 * 4]), as_float(words[11 * 4 + 1]), b_unit);
    report_mark(probe, words, extra);
    probe.next_draw();
  };

  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    glUseProgram(prog);
    if (frame > 0) draw_and_check(frame - 1);
    const int p = frame;
    const Units u = units(p);
    const float hv[3] = {static_cast<float>(p), p + 0.5f, p + 0.25f};
    const float xa[2] = {10.0f + p, 20.0f + p};
    if (p % 2 == 0) {
      glUniform1i(l_a, u.a);
      glUniform1i(l_b, u.b);
      glUniform1iv(l_u, 1, &u.u);
      glUniform1i(l_i, u.i);
      if (p % 4 == 0)
        glUniform1iv(l_arr, 3, u.arr);  // the whole array
      else
        for (int k = 0; k < 3; ++k) glUniform1i(l_arr + k, u.arr[k]);  // element by element
      glUniform1f(l_x, 100.5f + p);
      glUniform3fv(l_hv, 1, hv);
      glUniform1fv(l_xa, 2, xa);
      glUniform1i(l_free, p * 3 + 1);
    } else {
      glProgramUniform1i(prog, l_a, u.a);
      glProgramUniform1iv(prog, l_b, 1, &u.b);
      glProgramUniform1i(prog, l_u, u.u);
      glProgramUniform1i(prog, l_i, u.i);
      if (p % 4 == 1)
        for (int k = 0; k < 3; ++k) glProgramUniform1i(prog, l_arr + k, u.arr[k]);
      else
        glProgramUniform1iv(prog, l_arr, 3, u.arr);
      glProgramUniform1f(prog, l_x, 100.5f + p);
      glProgramUniform3f(prog, l_hv, hv[0], hv[1], hv[2]);
      glProgramUniform1f(prog, l_xa, xa[0]);
      glProgramUniform1f(prog, l_xa + 1, xa[1]);
      glProgramUniform1i(prog, l_free, p * 3 + 1);
    }
    probe.check_gl_error("after setting uniforms");
    draw_and_check(p);
    probe.check_gl_error("after drawing");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
