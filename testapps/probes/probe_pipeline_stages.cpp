// Program pipelines beside an ordinary program (issue 12, shadowing case 5). Three fragment
// programs whose sources all hold "PROBE_PIPELINE_STAGES", so one manifest pass matches each:
//   A: glCreateShaderProgramv, drawn in pipeline PA (with vertex program V, also
//      glCreateShaderProgramv);
//   B: separable, built with glProgramParameteri + glLinkProgram, drawn in pipeline PB;
//   C: an ordinary vertex + fragment program, drawn with glUseProgram.
// Each writes (VARIANT_MARK, 0x600d) in slot 0 and (u_val, its tag 0xA / 0xB / 0xC) in slot 1 of a
// GL_RGBA32UI target. Every frame: draw PA, PB, C, then PA again (after glUseProgram(0)), each
// with a new u_val (A: glActiveShaderProgram + glUniform1ui in even frames, glProgramUniform1ui
// in odd ones; B: glProgramUniform1ui; C: glUniform1ui). Checked here: u_val and the tag of
// every draw, GL_CURRENT_PROGRAM (0 with a pipeline, C with C) and GL_PROGRAM_PIPELINE_BINDING.
// Printed per draw: "frame F draw D mark M program X" (X: A, B or C), so a test sees which
// source each draw ran.
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

const char* const kSeparableVertex =
    "#version 450 core\n"
    "layout(location = 0) in vec2 pos;\n"
    "out gl_PerVertex { vec4 gl_Position; };\n"
    "void main() { gl_Position = vec4(pos, 0.0, 1.0); }\n";

std::string fragment(char tag) {
  return std::string(
             "#version 450 core\n"
             "// PROBE_PIPELINE_STAGES\n"
             "#define VARIANT_MARK 0\n"
             "uniform uint u_val;\n"
             "out uvec4 o;\n"
             "void main() {\n"
             "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
             "  int i = p.y * 4 + p.x;\n"
             "  o = i == 0 ? uvec4(uint(VARIANT_MARK), 0x600du, 0u, 0u) : i == 1 ? uvec4(u_val, 0x") +
         tag + "u, 0u, 0u) : uvec4(0xffffffffu);\n}\n";
}

GLuint shader_program(Probe& probe, GLenum stage, const std::string& source) {
  const char* text = source.c_str();
  const GLuint program = glCreateShaderProgramv(stage, 1, &text);
  return program && linked_or_say(probe.name(), program) ? program : 0;
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_pipeline_stages");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, 4, 4, &w)) return 2;
  const GLuint v = shader_program(probe, GL_VERTEX_SHADER, kSeparableVertex);
  const GLuint a = shader_program(probe, GL_FRAGMENT_SHADER, fragment('A'));
  const GLuint b = build_program(probe.name(), {{GL_FRAGMENT_SHADER, fragment('B')}},
                                 [](GLuint p) { glProgramParameteri(p, GL_PROGRAM_SEPARABLE, GL_TRUE); });
  const GLuint c =
      build_program(probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, fragment('C')}});
  if (!v || !a || !b || !c) return 2;
  GLuint pipelines[2] = {};
  glGenProgramPipelines(2, pipelines);
  const GLuint pa = pipelines[0], pb = pipelines[1];
  glUseProgramStages(pa, GL_VERTEX_SHADER_BIT, v);
  glUseProgramStages(pa, GL_FRAGMENT_SHADER_BIT, a);
  glUseProgramStages(pb, GL_VERTEX_SHADER_BIT, v);
  glUseProgramStages(pb, GL_FRAGMENT_SHADER_BIT, b);
  const GLint la = glGetUniformLocation(a, "u_val"), lb = glGetUniformLocation(b, "u_val"),
              lc = glGetUniformLocation(c, "u_val");
  if (la < 0 || lb < 0 || lc < 0) {
    std::fprintf(stderr, "probe_pipeline_stages: u_val has no location\n");
    return 2;
  }
  bind_fullscreen_quad(4, 4);
  SlotTarget target;
  if (!target.create(4, 4)) return 2;
  probe.check_gl_error("after setup");

  auto draw_and_check = [&](char tag, uint32_t value, GLint current_program, GLint pipeline) {
    GLint bound = -1, bound_pipeline = -1;
    glGetIntegerv(GL_CURRENT_PROGRAM, &bound);
    glGetIntegerv(GL_PROGRAM_PIPELINE_BINDING, &bound_pipeline);
    if (bound != current_program) probe.fail("GL_CURRENT_PROGRAM is %d, not %d", bound, current_program);
    if (bound_pipeline != pipeline) probe.fail("GL_PROGRAM_PIPELINE_BINDING is %d, not %d", bound_pipeline, pipeline);
    const std::vector<uint32_t> words = target.draw_and_read();
    const uint32_t expected[4] = {value, static_cast<uint32_t>(tag - 'A' + 0xA), 0, 0};
    expect_slot(probe, words, 1, expected, std::string("u_val and tag of program ") + tag);
    report_mark(probe, words, std::string("program ") + tag);
    probe.next_draw();
  };

  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    const uint32_t base = 0x1000u * static_cast<uint32_t>(frame + 1);
    glBindProgramPipeline(pa);
    if (frame % 2 == 0) {
      glActiveShaderProgram(pa, a);
      glUniform1ui(la, base + 1);  // to the pipeline's active program
    } else {
      glProgramUniform1ui(a, la, base + 1);
    }
    draw_and_check('A', base + 1, 0, static_cast<GLint>(pa));
    glBindProgramPipeline(pb);
    glProgramUniform1ui(b, lb, base + 2);
    draw_and_check('B', base + 2, 0, static_cast<GLint>(pb));
    glUseProgram(c);  // takes precedence over the bound pipeline
    glUniform1ui(lc, base + 3);
    draw_and_check('C', base + 3, static_cast<GLint>(c), static_cast<GLint>(pb));
    glUseProgram(0);
    glBindProgramPipeline(pa);
    glProgramUniform1ui(a, la, base + 4);
    draw_and_check('A', base + 4, 0, static_cast<GLint>(pa));
    probe.check_gl_error("after drawing");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
