// Variants that cannot be built (issue 12, shadowing case 8): the fragment source uses a macro
// BAD (`#define BAD 1`) that a manifest level may redefine to something that does not compile,
// and a level may replace the fragment stage with one that does not link. The app draws as
// usual: two programs of the same sources (so glbudget meets the same failing variant twice),
// each with its own u_val, every frame; slot 1 of a GL_RGBA32UI target holds (u_val, BAD, 0x5a).
// Checked here: every draw shows the values the app set and BAD = 1, and an error the app
// raised before linking is still its to read after (glbudget builds its variants, and reads
// the errors that raises, inside the app's glLinkProgram). Printed per draw:
// "frame F draw D mark M" (VARIANT_MARK).
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

const char* const kFragment =
    "#version 450 core\n"
    "// PROBE_BAD_VARIANT\n"
    "#define VARIANT_MARK 0\n"
    "#define BAD 1\n"
    "uniform uint u_val;\n"
    "out uvec4 o;\n"
    "void main() {\n"
    "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
    "  int i = p.y * 4 + p.x;\n"
    "  uint bad = uint(BAD);\n"
    "  o = i == 0 ? uvec4(uint(VARIANT_MARK), 0x600du, 0u, 0u) : i == 1 ? uvec4(u_val, bad, 0x5au, 0u) : "
    "uvec4(0xffffffffu);\n"
    "}\n";

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_bad_variant");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, 4, 4, &w)) return 2;
  probe.check_gl_error("before linking");
  glBindBuffer(0x1234, 0);  // the app's own GL_INVALID_ENUM, left pending across its links
  GLuint progs[2];
  for (GLuint& p : progs) {
    p = build_program(probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, kFragment}});
    if (!p) return 2;
  }
  const GLenum first = glGetError(), second = glGetError();
  if (first != GL_INVALID_ENUM || second != GL_NO_ERROR)
    probe.fail("after linking, glGetError() = 0x%04x then 0x%04x; the app's GL_INVALID_ENUM then none expected", first,
               second);
  bind_fullscreen_quad(4, 4);
  SlotTarget target;
  if (!target.create(4, 4)) return 2;
  probe.check_gl_error("after setup");

  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    for (int k = 0; k < 2; ++k) {
      glUseProgram(progs[k]);
      const uint32_t value = 0x100u * static_cast<uint32_t>(frame + 1) + static_cast<uint32_t>(k);
      glUniform1ui(glGetUniformLocation(progs[k], "u_val"), value);
      const std::vector<uint32_t> words = target.draw_and_read();
      const uint32_t expected[4] = {value, 1, 0x5a, 0};
      expect_slot(probe, words, 1, expected, "u_val, BAD of program " + std::to_string(k));
      report_mark(probe, words);
      probe.next_draw();
    }
    probe.check_gl_error("after drawing");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
