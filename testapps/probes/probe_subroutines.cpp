// Subroutine uniforms (GL 4.0; issue 12, shadowing case 1 continued): the fragment shader's
// u_pick selects one of pick_a, pick_b, pick_c (0xa, 0xb, 0xc in slot 1 of a GL_RGBA32UI target).
// With EXTRA_FUNCTION != 0 the source declares one more subroutine function ahead of them, so a
// variant's subroutine indices differ from the app's (the mark is VARIANT_MARK, as elsewhere).
// GL resets subroutine selections at glUseProgram (and nowhere else): an app may select once
// after binding its program and draw with it for many frames. Here:
//   frame 0: glUseProgram, select pick_b (glGetSubroutineIndex + glUniformSubroutinesuiv); draw
//   frames 1, 2: draw, nothing else
//   frame 3: glUseProgram, select pick_c; draw
//   frames 4, 5: draw
// Checked here: each draw ran the function last selected (glGetUniformSubroutineuiv must
// also answer with the app's index). Printed per draw: "frame F draw D mark M".
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

const char* const kFragment =
    "#version 450 core\n"
    "// PROBE_SUBROUTINES\n"
    "#define VARIANT_MARK 0\n"
    "#define EXTRA_FUNCTION 0\n"
    "subroutine uint Pick();\n"
    "#if EXTRA_FUNCTION\n"
    "subroutine(Pick) uint pick_extra() { return 0xeeeeu; }\n"
    "#endif\n"
    "subroutine(Pick) uint pick_a() { return 0xau; }\n"
    "subroutine(Pick) uint pick_b() { return 0xbu; }\n"
    "subroutine(Pick) uint pick_c() { return 0xcu; }\n"
    "subroutine uniform Pick u_pick;\n"
    "out uvec4 o;\n"
    "void main() {\n"
    "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
    "  int i = p.y * 4 + p.x;\n"
    "  o = i == 0 ? uvec4(uint(VARIANT_MARK), 0x600du, 0u, 0u) : i == 1 ? uvec4(u_pick(), 0u, 0u, 0u) : "
    "uvec4(0xffffffffu);\n"
    "}\n";

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_subroutines");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, 4, 4, &w)) return 2;
  const GLuint prog =
      build_program(probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, kFragment}});
  if (!prog) return 2;
  const GLuint index_b = glGetSubroutineIndex(prog, GL_FRAGMENT_SHADER, "pick_b");
  const GLuint index_c = glGetSubroutineIndex(prog, GL_FRAGMENT_SHADER, "pick_c");
  const GLint location = glGetSubroutineUniformLocation(prog, GL_FRAGMENT_SHADER, "u_pick");
  GLint locations = 0;
  glGetProgramStageiv(prog, GL_FRAGMENT_SHADER, GL_ACTIVE_SUBROUTINE_UNIFORM_LOCATIONS, &locations);
  if (index_b == GL_INVALID_INDEX || index_c == GL_INVALID_INDEX || location != 0 || locations != 1) {
    std::fprintf(stderr, "probe_subroutines: unexpected subroutine interface\n");
    return 2;
  }
  bind_fullscreen_quad(4, 4);
  SlotTarget target;
  if (!target.create(4, 4)) return 2;
  probe.check_gl_error("after setup");

  uint32_t selected = 0;
  GLuint selected_index = 0;
  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    if (frame == 0 || frame == 3) {
      glUseProgram(prog);
      selected_index = frame == 0 ? index_b : index_c;
      selected = frame == 0 ? 0xbu : 0xcu;
      glUniformSubroutinesuiv(GL_FRAGMENT_SHADER, 1, &selected_index);
      probe.check_gl_error("after glUniformSubroutinesuiv");
    }
    GLuint answered = 0xffffffffu;
    glGetUniformSubroutineuiv(GL_FRAGMENT_SHADER, location, &answered);
    if (answered != selected_index)
      probe.fail("glGetUniformSubroutineuiv answers %u, not the %u selected", answered, selected_index);
    const std::vector<uint32_t> words = target.draw_and_read();
    const uint32_t expected[4] = {selected, 0, 0, 0};
    expect_slot(probe, words, 1, expected, "the function u_pick selects");
    report_mark(probe, words);
    probe.next_draw();
    probe.check_gl_error("after drawing");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
