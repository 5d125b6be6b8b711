// What the app can ask about its program (issue 12, shadowing case 7): uniform locations
// (glGetUniformLocation, glGetProgramResourceLocation, glGetUniformIndices, glGetActiveUniform),
// attribute and output locations, uniform and storage block indices, the program's counts and
// GL_CURRENT_PROGRAM through every glGet* form. Printed on stdout, one "query ..." line each,
// every frame, with the program bound, after a draw, and after glUseProgram of another program
// and of 0, so a test can compare a run under glbudget (any level) with a run without it line for
// line. Object names differ between such runs (glbudget makes programs and shaders of its own), so
// GL_CURRENT_PROGRAM is printed as which of the app's programs it names. Draws also print
// "frame F draw D mark M" (VARIANT_MARK, as in the other shadowing probes), which is expected
// to differ by level. Values read back with glGetUniform* after the app set them are printed too.
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

const char* const kVertex =
    "#version 450 core\n"
    "// PROBE_LOCATIONS\n"
    "#define VARIANT_MARK 0\n"
    "#if VARIANT_MARK\n"
    "in vec4 a_extra;\n"
    "#define SHIFT a_extra.x\n"
    "#else\n"
    "#define SHIFT 0.0\n"
    "#endif\n"
    "in vec2 pos;\n"
    "in vec3 normal;\n"
    "layout(location = 5) in vec2 uv;\n"
    "in float unused_attribute;\n"
    "flat out float v_sum;\n"
    "void main() {\n"
    "  gl_Position = vec4(pos, 0.0, 1.0);\n"
    "  v_sum = normal.x + uv.y + SHIFT;\n"
    "}\n";

const char* const kFragment =
    "#version 450 core\n"
    "#define VARIANT_MARK 0\n"
    "#if VARIANT_MARK\n"
    "uniform vec4 a_extra_u[4];\n"
    "layout(std140) uniform AExtra { vec4 e; };\n"
    "layout(std430) readonly buffer AExtraS { vec4 es; };\n"
    "#define MARK_SHIFT uint(a_extra_u[3].w + e.w + es.w > 1e30)\n"
    "#else\n"
    "#define MARK_SHIFT 0u\n"
    "#endif\n"
    "struct Light { vec3 dir; float power[2]; };\n"
    "flat in float v_sum;\n"
    "uniform float u_f;\n"
    "uniform vec4 u_arr[3];\n"
    "uniform Light u_light[2];\n"
    "uniform mat3 u_m;\n"
    "layout(location = 9) uniform int u_fixed;\n"
    "uniform float u_unused;\n"
    "layout(std140) uniform Globals { vec4 g; };\n"
    "layout(std140) uniform PerDraw { vec4 d; } per_draw[2];\n"
    "layout(std430) readonly buffer Data { vec4 values[]; };\n"
    "out uvec4 o;\n"
    "layout(location = 1) out vec4 o_second;\n"
    "void main() {\n"
    "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
    "  float sum = v_sum + u_f + u_arr[2].x + u_light[1].dir.y + u_light[1].power[1] + u_m[2][2] + float(u_fixed) +\n"
    "              g.x + per_draw[1].d.x + values[0].x;\n"
    "  o = p.x + p.y == 0 ? uvec4(uint(VARIANT_MARK) + MARK_SHIFT, 0x600du, floatBitsToUint(sum), 0u) : uvec4(0u);\n"
    "  o_second = vec4(sum);\n"
    "}\n";

const char* const kOtherFragment =
    "#version 450 core\n"
    "out uvec4 o;\n"
    "void main() { o = uvec4(1u); }\n";

void query_program(GLuint prog) {
  for (const char* name : {"u_f", "u_arr", "u_arr[0]", "u_arr[2]", "u_light[0].dir", "u_light[1].power",
                           "u_light[1].power[1]", "u_m", "u_fixed", "u_unused", "a_extra_u", "nope", "g"}) {
    std::printf("query uniform %s location %d resource-location %d\n", name, glGetUniformLocation(prog, name),
                glGetProgramResourceLocation(prog, GL_UNIFORM, name));
  }
  const char* names[3] = {"u_m", "u_light[1].dir", "u_arr[0]"};
  GLuint indices[3] = {};
  glGetUniformIndices(prog, 3, names, indices);
  std::printf("query uniform indices %d %d %d\n", static_cast<int>(indices[0]), static_cast<int>(indices[1]),
              static_cast<int>(indices[2]));
  GLint count = 0;
  glGetProgramiv(prog, GL_ACTIVE_UNIFORMS, &count);
  std::printf("query active uniforms %d\n", count);
  for (GLint i = 0; i < count; ++i) {
    char name[128] = {};
    GLint size = 0;
    GLenum type = 0;
    glGetActiveUniform(prog, static_cast<GLuint>(i), sizeof name, nullptr, &size, &type, name);
    std::printf("query active uniform %d %s size %d type 0x%x location %d\n", i, name, size, type,
                glGetUniformLocation(prog, name));
  }
  for (const char* name : {"pos", "normal", "uv", "unused_attribute", "a_extra", "nope"})
    std::printf("query attribute %s location %d\n", name, glGetAttribLocation(prog, name));
  glGetProgramiv(prog, GL_ACTIVE_ATTRIBUTES, &count);
  std::printf("query active attributes %d\n", count);
  for (const char* name : {"o", "o_second", "nope"})
    std::printf("query output %s location %d\n", name, glGetFragDataLocation(prog, name));
  for (const char* name : {"Globals", "PerDraw", "PerDraw[0]", "PerDraw[1]", "AExtra", "nope"})
    std::printf("query uniform block %s index %d\n", name, static_cast<int>(glGetUniformBlockIndex(prog, name)));
  glGetProgramiv(prog, GL_ACTIVE_UNIFORM_BLOCKS, &count);
  std::printf("query active uniform blocks %d\n", count);
  for (const char* name : {"Data", "AExtraS", "nope"})
    std::printf("query storage block %s index %d\n", name,
                static_cast<int>(glGetProgramResourceIndex(prog, GL_SHADER_STORAGE_BLOCK, name)));
  glGetProgramInterfaceiv(prog, GL_SHADER_STORAGE_BLOCK, GL_ACTIVE_RESOURCES, &count);
  std::printf("query active storage blocks %d\n", count);
  GLint status = 0, shaders = 0;
  glGetProgramiv(prog, GL_LINK_STATUS, &status);
  glGetProgramiv(prog, GL_ATTACHED_SHADERS, &shaders);
  std::printf("query link status %d attached shaders %d\n", status, shaders);
}

// Which of the app's programs GL_CURRENT_PROGRAM names, through each glGet form.
void query_current(const char* when, GLuint prog, GLuint other) {
  auto which = [&](double v) -> std::string {
    if (v == 0) return "none";
    if (v == prog) return "program";
    if (v == other) return "other";
    return "unknown " + std::to_string(v);
  };
  GLint i = -1;
  GLint64 i64 = -1;
  GLfloat f = -1;
  GLdouble d = -1;
  GLboolean b = 7;
  glGetIntegerv(GL_CURRENT_PROGRAM, &i);
  glGetInteger64v(GL_CURRENT_PROGRAM, &i64);
  glGetFloatv(GL_CURRENT_PROGRAM, &f);
  glGetDoublev(GL_CURRENT_PROGRAM, &d);
  glGetBooleanv(GL_CURRENT_PROGRAM, &b);
  std::printf("query current program %s: integer %s integer64 %s float %s double %s boolean %d\n", when,
              which(i).c_str(), which(static_cast<double>(i64)).c_str(), which(f).c_str(), which(d).c_str(), b);
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_locations");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, 4, 4, &w)) return 2;
  const GLuint prog =
      build_program(probe.name(), {{GL_VERTEX_SHADER, kVertex}, {GL_FRAGMENT_SHADER, kFragment}}, [](GLuint p) {
        glBindAttribLocation(p, 0, "pos");
        glBindAttribLocation(p, 3, "normal");
      });
  const GLuint other =
      build_program(probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, kOtherFragment}});
  if (!prog || !other) return 2;
  GLuint buffers[2] = {};
  glGenBuffers(2, buffers);
  const float zeros[16] = {};
  glBindBuffer(GL_UNIFORM_BUFFER, buffers[0]);
  glBufferData(GL_UNIFORM_BUFFER, sizeof zeros, zeros, GL_STATIC_DRAW);
  glBindBufferBase(GL_UNIFORM_BUFFER, 0, buffers[0]);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffers[1]);
  glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof zeros, zeros, GL_STATIC_DRAW);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, buffers[1]);
  bind_fullscreen_quad(4, 4);
  SlotTarget target;
  if (!target.create(4, 4)) return 2;
  probe.check_gl_error("after setup");

  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    std::printf("query frame %d\n", frame);
    query_current("before glUseProgram", prog, other);
    glUseProgram(prog);
    query_current("bound", prog, other);
    query_program(prog);
    glUniform1f(glGetUniformLocation(prog, "u_f"), 0.5f + static_cast<float>(frame));
    glUniform4f(glGetUniformLocation(prog, "u_arr") + 2, 1, 2, 3, static_cast<float>(frame));
    glUniform1i(9, frame * 11);  // the explicit location
    glUniform1f(glGetUniformLocation(prog, "u_light[1].power") + 1, 4.0f * static_cast<float>(frame));
    GLfloat v4[4] = {};
    GLfloat power = 0, f = 0;
    GLint fixed = 0;
    glGetUniformfv(prog, glGetUniformLocation(prog, "u_f"), &f);
    glGetUniformfv(prog, glGetUniformLocation(prog, "u_arr[2]"), v4);
    glGetUniformfv(prog, glGetUniformLocation(prog, "u_light[1].power[1]"), &power);
    glGetUniformiv(prog, 9, &fixed);
    std::printf("query values u_f %g u_arr[2] %g %g %g %g u_light[1].power[1] %g u_fixed %d\n", f, v4[0], v4[1], v4[2],
                v4[3], power, fixed);
    const std::vector<uint32_t> words = target.draw_and_read();
    report_mark(probe, words);
    probe.next_draw();
    query_current("after a draw", prog, other);
    glUseProgram(other);
    query_current("other bound", prog, other);
    glUseProgram(0);
    query_current("none bound", prog, other);
    glUseProgram(prog);
    query_current("bound again", prog, other);
    probe.check_gl_error("after the queries");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
