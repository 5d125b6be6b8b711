// Uniform and shader-storage block bindings (issue 12, shadowing case 3). Eight uniform
// buffers on uniform binding points 0-7 and eight storage buffers on storage binding points 0-7,
// each holding a uvec4 that names it; the fragment shader copies what each of its blocks holds
// into a slot, so a read-back names the binding point each block reads. Every frame the app
// rebinds its blocks to other points with glUniformBlockBinding / glShaderStorageBlockBinding
// (block indices from glGetUniformBlockIndex / glGetProgramResourceIndex); UFixed and SFixed keep
// the bindings their `layout(binding = N)` gives. Blocks: UA (instance name), UB (none), UArr[2]
// (an array of blocks), UFixed; SA, SB (runtime-sized array), SFixed.
// Each frame: a draw that must show the previous frame's bindings (set before the swap), new
// bindings, a draw that must show them.
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

const char* const kFragment =
    "#version 450 core\n"
    "// PROBE_BLOCKS\n"
    "#define VARIANT_MARK 0\n"
    "#if VARIANT_MARK\n"
    "layout(std140) uniform AExtra { vec4 x; } a_extra;\n"
    "layout(std430) readonly buffer AExtraS { vec4 y; } a_extra_s;\n"
    "#define MARK_SHIFT uint(a_extra.x.w + a_extra_s.y.w > 1e30)\n"
    "#else\n"
    "#define MARK_SHIFT 0u\n"
    "#endif\n"
    "layout(std140) uniform UA { uvec4 a; } ua;\n"
    "layout(std140) uniform UB { uvec4 b; };\n"
    "layout(std140) uniform UArr { uvec4 v; } uarr[2];\n"
    "layout(std140, binding = 7) uniform UFixed { uvec4 f; } ufixed;\n"
    "layout(std430) readonly buffer SA { uvec4 s; } sa;\n"
    "layout(std430) readonly buffer SB { uvec4 t[]; } sb;\n"
    "layout(std430, binding = 6) readonly buffer SFixed { uvec4 g; } sfixed;\n"
    "out uvec4 o;\n"
    "uvec4 slot(int i) {\n"
    "  switch (i) {\n"
    "    case 0: return uvec4(uint(VARIANT_MARK) + MARK_SHIFT, 0x600du, 0u, 0u);\n"
    "    case 1: return ua.a;\n"
    "    case 2: return b;\n"
    "    case 3: return uarr[0].v;\n"
    "    case 4: return uarr[1].v;\n"
    "    case 5: return ufixed.f;\n"
    "    case 6: return sa.s;\n"
    "    case 7: return sb.t[0];\n"
    "    case 8: return sfixed.g;\n"
    "  }\n"
    "  return uvec4(0xffffffffu);\n"
    "}\n"
    "void main() { ivec2 p = ivec2(gl_FragCoord.xy); o = slot(p.y * 4 + p.x); }\n";

constexpr int kBindings = 8;

void buffer_words(bool storage, int binding, uint32_t out[4]) {
  const uint32_t k = static_cast<uint32_t>(binding);
  out[0] = (storage ? 0x5000u : 0x0b00u) + k;
  out[1] = k * 3 + 1;
  out[2] = ~k;
  out[3] = storage ? 0x55555555u : 0xbbbbbbbbu;
}

// The binding points each block uses in phase p (UFixed 7 and SFixed 6 always).
struct Bindings {
  int ua, ub, uarr[2], sa, sb;
};
Bindings bindings(int p) { return {p % 6, (p + 1) % 6, {(p + 2) % 6, (p + 3) % 6}, p % 5, (p + 2) % 5}; }

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_blocks");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, 4, 4, &w)) return 2;
  const GLuint prog =
      build_program(probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, kFragment}});
  if (!prog) return 2;
  for (int storage = 0; storage < 2; ++storage)
    for (int k = 0; k < kBindings; ++k) {
      uint32_t words[4];
      buffer_words(storage, k, words);
      GLuint buffer = 0;
      glGenBuffers(1, &buffer);
      const GLenum target = storage ? GL_SHADER_STORAGE_BUFFER : GL_UNIFORM_BUFFER;
      glBindBuffer(target, buffer);
      glBufferData(target, sizeof words, words, GL_STATIC_DRAW);
      glBindBufferBase(target, static_cast<GLuint>(k), buffer);
    }
  const GLuint i_ua = glGetUniformBlockIndex(prog, "UA"), i_ub = glGetUniformBlockIndex(prog, "UB");
  const GLuint i_arr0 = glGetUniformBlockIndex(prog, "UArr[0]"), i_arr1 = glGetUniformBlockIndex(prog, "UArr[1]");
  const GLuint i_sa = glGetProgramResourceIndex(prog, GL_SHADER_STORAGE_BLOCK, "SA");
  const GLuint i_sb = glGetProgramResourceIndex(prog, GL_SHADER_STORAGE_BLOCK, "SB");
  for (GLuint i : {i_ua, i_ub, i_arr0, i_arr1, i_sa, i_sb})
    if (i == GL_INVALID_INDEX) {
      std::fprintf(stderr, "probe_blocks: a block has no index\n");
      return 2;
    }
  bind_fullscreen_quad(4, 4);
  SlotTarget target;
  if (!target.create(4, 4)) return 2;
  probe.check_gl_error("after setup");

  auto draw_and_check = [&](int p) {
    const std::vector<uint32_t> words = target.draw_and_read();
    report_mark(probe, words, "phase " + std::to_string(p));
    const Bindings b = bindings(p);
    uint32_t expected[4];
    const std::pair<int, const char*> uniform_blocks[] = {{b.ua, "UA"},
                                                          {b.ub, "UB"},
                                                          {b.uarr[0], "UArr[0]"},
                                                          {b.uarr[1], "UArr[1]"},
                                                          {7, "UFixed (layout(binding = 7))"}};
    for (int k = 0; k < 5; ++k) {
      buffer_words(false, uniform_blocks[k].first, expected);
      expect_slot(probe, words, 1 + k, expected, uniform_blocks[k].second + std::string(" phase ") + std::to_string(p));
    }
    const std::pair<int, const char*> storage_blocks[] = {
        {b.sa, "SA"}, {b.sb, "SB"}, {6, "SFixed (layout(binding = 6))"}};
    for (int k = 0; k < 3; ++k) {
      buffer_words(true, storage_blocks[k].first, expected);
      expect_slot(probe, words, 6 + k, expected, storage_blocks[k].second + std::string(" phase ") + std::to_string(p));
    }
    probe.next_draw();
  };

  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    glUseProgram(prog);
    if (frame > 0) draw_and_check(frame - 1);
    const Bindings b = bindings(frame);
    glUniformBlockBinding(prog, i_ua, static_cast<GLuint>(b.ua));
    glUniformBlockBinding(prog, i_ub, static_cast<GLuint>(b.ub));
    glUniformBlockBinding(prog, i_arr0, static_cast<GLuint>(b.uarr[0]));
    glUniformBlockBinding(prog, i_arr1, static_cast<GLuint>(b.uarr[1]));
    glShaderStorageBlockBinding(prog, i_sa, static_cast<GLuint>(b.sa));
    glShaderStorageBlockBinding(prog, i_sb, static_cast<GLuint>(b.sb));
    probe.check_gl_error("after binding blocks");
    draw_and_check(frame);
    probe.check_gl_error("after drawing");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
