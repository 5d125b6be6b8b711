// A program the app relinks with new sources (issue 12, shadowing case 6): glShaderSource +
// glCompileShader on its fragment shader, then glLinkProgram on the same program id. Versions
// of the fragment source (slot 1 of a GL_RGBA32UI target holds (u_a, u_b, version, extra)):
//   1: uniforms u_a, u_b; extra 0                  holds "PROBE_RELINK"
//   2: u_new, u_b, u_a (other order, one more); extra u_new    holds "PROBE_RELINK"
//   3: u_a, u_b; extra 0                           does not hold it (no manifest pass matches)
//   4: u_c[2], u_a, u_b; extra u_c[1]              holds "PROBE_RELINK"
// Every frame draws; a frame that relinks then sets the new version's uniforms and draws again.
// `--scenario matched` (the default) relinks only to sources the manifest matches:
//   frame 1: to version 2 while the program is bound
//   frame 3: glUseProgram(0), to version 4, glUseProgram(program)
//   frame 4: to version 1 while the program is bound
// `--scenario unmatched` also relinks to a source no manifest pass matches, and back:
//   frame 1: to version 3 while the program is bound
//   frame 2: to version 2 while the program is bound
//   frame 4: to version 3 while the program is bound
//   frame 5: to version 4 while the program is bound
// `--scenario deleted` relinks nothing: in frame 0, after its draw, the app deletes its program
// while it is bound (GL keeps it until it is no longer in use) and goes on drawing with it,
// setting u_a with glUniform1ui and u_b with glProgramUniform1ui every frame, never calling
// glUseProgram again.
// Checked here: each draw shows the version last linked and the values set since, and
// GL_CURRENT_PROGRAM names the program. Printed per
// draw: "frame F draw D mark M version V", V the version that drew (the mark is VARIANT_MARK: a
// test can tell whether a variant of the right version drew).
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

std::string fragment(int version) {
  std::string s = "#version 450 core\n";
  s += version == 3 ? "// relinked: no manifest pass names this source\n" : "// PROBE_RELINK\n";
  s += "#define VARIANT_MARK 0\n";
  switch (version) {
    case 1:
      s += "uniform uint u_a;\nuniform uint u_b;\n#define EXTRA 0u\n";
      break;
    case 2:
      s += "uniform uint u_new;\nuniform uint u_b;\nuniform uint u_a;\n#define EXTRA u_new\n";
      break;
    case 3:
      s += "uniform uint u_a;\nuniform uint u_b;\n#define EXTRA 0u\n";
      break;
    default:
      s += "uniform uint u_c[2];\nuniform uint u_a;\nuniform uint u_b;\n#define EXTRA u_c[1]\n";
      break;
  }
  s += "out uvec4 o;\n"
       "void main() {\n"
       "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
       "  int i = p.y * 4 + p.x;\n"
       "  o = i == 0 ? uvec4(uint(VARIANT_MARK), 0x600du, 0u, 0u) : i == 1 ? uvec4(u_a, u_b, " +
       std::to_string(version) + "u, EXTRA) : uvec4(0xffffffffu);\n}\n";
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_relink");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, 4, 4, &w)) return 2;
  std::vector<GLuint> shaders;
  const GLuint prog = build_program(
      probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, fragment(1)}}, {}, &shaders);
  if (!prog) return 2;
  const GLuint fs = shaders[1];
  bind_fullscreen_quad(4, 4);
  SlotTarget target;
  if (!target.create(4, 4)) return 2;
  probe.check_gl_error("after setup");

  int version = 1;
  uint32_t a = 0, b = 0, extra = 0;
  // Sets the uniforms of the version last linked (locations queried afresh).
  auto set_uniforms = [&](uint32_t base) {
    a = base + 1;
    b = base + 2;
    extra = version == 2 || version == 4 ? base + 3 : 0;
    glUniform1ui(glGetUniformLocation(prog, "u_a"), a);
    glProgramUniform1ui(prog, glGetUniformLocation(prog, "u_b"), b);
    if (version == 2) glUniform1ui(glGetUniformLocation(prog, "u_new"), extra);
    if (version == 4) {
      const GLint c = glGetUniformLocation(prog, "u_c");
      const GLuint both[2] = {0x77u, extra};
      glUniform1uiv(c, 2, both);
    }
  };
  auto draw_and_check = [&]() {
    GLint current = -1;
    glGetIntegerv(GL_CURRENT_PROGRAM, &current);
    if (current != static_cast<GLint>(prog)) probe.fail("GL_CURRENT_PROGRAM is %d, not the program %u", current, prog);
    const std::vector<uint32_t> words = target.draw_and_read();
    const uint32_t expected[4] = {a, b, static_cast<uint32_t>(version), extra};
    expect_slot(probe, words, 1, expected, "u_a, u_b, version, extra of version " + std::to_string(version));
    report_mark(probe, words, "version " + std::to_string(words[4 + 2]));  // the version that drew
    probe.next_draw();
  };
  auto relink = [&](int to) {
    const std::string source = fragment(to);
    const char* text = source.c_str();
    glShaderSource(fs, 1, &text, nullptr);
    glCompileShader(fs);
    GLint ok = 0;
    glGetShaderiv(fs, GL_COMPILE_STATUS, &ok);
    glLinkProgram(prog);
    if (!ok || !linked_or_say(probe.name(), prog)) probe.fail("version %d does not build", to);
    version = to;
  };

  // Frame -> the version it relinks to; negative: with the program unbound around the relink.
  std::map<int, int> relinks = {{1, 2}, {3, -4}, {4, 1}};
  bool delete_bound = false;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--scenario") != 0) continue;
    if (std::strcmp(argv[i + 1], "unmatched") == 0) relinks = {{1, 3}, {2, 2}, {4, 3}, {5, 4}};
    if (std::strcmp(argv[i + 1], "deleted") == 0) {
      relinks.clear();
      delete_bound = true;
    }
  }
  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    const uint32_t base = 0x100u * static_cast<uint32_t>(frame + 1);
    if (!delete_bound || frame == 0) glUseProgram(prog);
    if (frame == 0 || delete_bound) set_uniforms(base);
    draw_and_check();
    if (delete_bound && frame == 0) {
      glDeleteProgram(prog);  // flagged: it stays in use, and its name valid, until unbound
      probe.check_gl_error("after glDeleteProgram of the bound program");
    }
    if (auto it = relinks.find(frame); it != relinks.end()) {
      if (it->second < 0) glUseProgram(0);
      relink(it->second < 0 ? -it->second : it->second);
      if (it->second < 0) glUseProgram(prog);
      set_uniforms(base);
      draw_and_check();
    }
    probe.check_gl_error("after drawing");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
