// Vertex attributes and fragment outputs at the locations the app chose (issue 12, shadowing
// case 4). Attributes: pos, color, ints bound by glBindAttribLocation before the link (to 4, 1
// and 3: none where the linker would put them), weight bound to 6 and fed as a current value
// (glVertexAttrib1f, no array), lay at `layout(location = 2)`. Outputs: outA and outB bound by
// glBindFragDataLocation to 1 and 0 (the reverse of their order), outC at `layout(location = 2)`
// (a GL_RGBA32UI attachment: the mark and the integer attribute). Every attribute is flat, the
// same at each vertex, and changes every frame (glBufferSubData, glVertexAttrib1f), so each
// attachment read back names what arrived where:
//   attachment 0 = outB = (lay, weight), 1 = outA = color, 2 = outC = (mark, 0x600d, ints).
// With VARIANT_MARK != 0 both stages declare an attribute or output more, ahead of the app's.
//
// `--scenario inactive`: the app also binds names its program does not have, as apps that bind
// one fixed scheme for every program do: glBindAttribLocation(7, "tangent"),
// glBindFragDataLocation(4, "outD") and (3, "outE"). Only with VARIANT_MARK != 0 do the sources
// declare them: tangent (attribute 7 holds (0, 0, 0, 0); any other location gives w = 1) adds
// 100 * tangent.w to the mark, outD writes 42 and outE 43 (declared in that order, bound in the
// other). A variant built as the app would have built that source has tangent at 7, outE at 3
// and outD at 4: mark 1, 43s in attachment 3 and 42s in attachment 4 (unchecked at mark 0,
// where nothing writes them).
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

const char* const kVertexInactive =
    "#if VARIANT_MARK\n"
    "in vec4 tangent;\n"
    "#define TANGENT_SHIFT (tangent.w * 100.0)\n"
    "#else\n"
    "#define TANGENT_SHIFT 0.0\n"
    "#endif\n";

const char* const kVertex =
    "#if VARIANT_MARK\n"
    "in vec4 a_extra0;\n"
    "in vec4 a_extra1;\n"
    "#define MARK_SHIFT (a_extra0.x + a_extra1.y + TANGENT_SHIFT)\n"
    "#else\n"
    "#define MARK_SHIFT 0.0\n"
    "#endif\n"
    "in vec2 pos;\n"
    "in vec4 color;\n"
    "in float weight;\n"
    "layout(location = 2) in vec3 lay;\n"
    "in ivec2 ints;\n"
    "flat out vec4 v_color;\n"
    "flat out vec4 v_lay_weight;\n"
    "flat out ivec2 v_ints;\n"
    "flat out float v_mark;\n"
    "void main() {\n"
    "  gl_Position = vec4(pos, 0.0, 1.0);\n"
    "  v_color = color;\n"
    "  v_lay_weight = vec4(lay, weight);\n"
    "  v_ints = ints;\n"
    "  v_mark = float(VARIANT_MARK) + MARK_SHIFT;\n"
    "}\n";

// The sources: VARIANT_MARK first, then the scenario's lines, then the common part.
std::string vertex_source(bool inactive) {
  return std::string("#version 450 core\n// PROBE_ATTRIBUTES\n#define VARIANT_MARK 0\n") +
         (inactive ? kVertexInactive : "#define TANGENT_SHIFT 0.0\n") + kVertex;
}

const char* const kFragmentInactive =
    "#if VARIANT_MARK\n"
    "out vec4 outD;\n"
    "out vec4 outE;\n"
    "#define WRITE_D outD = vec4(42.0); outE = vec4(43.0);\n"
    "#endif\n";

const char* const kFragment =
    "#ifndef WRITE_D\n"
    "#define WRITE_D\n"
    "#endif\n"
    "#if VARIANT_MARK\n"
    "out vec4 a_extra_out;\n"
    "#endif\n"
    "flat in vec4 v_color;\n"
    "flat in vec4 v_lay_weight;\n"
    "flat in ivec2 v_ints;\n"
    "flat in float v_mark;\n"
    "out vec4 outA;\n"
    "out vec4 outB;\n"
    "layout(location = 2) out uvec4 outC;\n"
    "void main() {\n"
    "#if VARIANT_MARK\n"
    "  a_extra_out = vec4(0.0);\n"
    "#endif\n"
    "  WRITE_D\n"
    "  outA = v_color;\n"
    "  outB = v_lay_weight;\n"
    "  outC = uvec4(uint(v_mark), 0x600du, uvec2(v_ints));\n"
    "}\n";

std::string fragment_source(bool inactive) {
  return std::string("#version 450 core\n#define VARIANT_MARK 0\n") + (inactive ? kFragmentInactive : "") + kFragment;
}

constexpr int kSide = 4;
constexpr GLuint kPos = 4, kColor = 1, kLay = 2, kInts = 3, kWeight = 6, kTangent = 7;

struct Values {
  float color[4], lay[3], weight;
  int32_t ints[2];
};
Values values(int p) {
  const float f = static_cast<float>(p);
  return {{f + 0.25f, f + 0.5f, f + 0.75f, f + 1.0f}, {10 + f, 20 + f, 30 + f}, 0.125f * f + 7.0f, {-p - 1, 1000 + p}};
}

// One buffer per attribute, six identical vertices each (pos: the quad).
struct Arrays {
  GLuint color = 0, lay = 0, ints = 0;
};

template <typename T, size_t N>
void fill(GLuint buffer, const T (&one)[N]) {
  std::vector<T> six;
  for (int v = 0; v < 6; ++v) six.insert(six.end(), one, one + N);
  glBindBuffer(GL_ARRAY_BUFFER, buffer);
  glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(six.size() * sizeof(T)), six.data());
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_attributes");
  EglFns egl;
  EglWindow w;
  bool inactive = false;  // options come in pairs, as in parse_probe_args
  for (int i = 1; i + 1 < argc; i += 2)
    inactive = inactive || (std::strcmp(argv[i], "--scenario") == 0 && std::strcmp(argv[i + 1], "inactive") == 0);
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, kSide, kSide, &w)) return 2;
  const GLuint prog = build_program(
      probe.name(), {{GL_VERTEX_SHADER, vertex_source(inactive)}, {GL_FRAGMENT_SHADER, fragment_source(inactive)}},
      [inactive](GLuint p) {
        glBindAttribLocation(p, kPos, "pos");
        glBindAttribLocation(p, kColor, "color");
        glBindAttribLocation(p, kInts, "ints");
        glBindAttribLocation(p, kWeight, "weight");
        glBindFragDataLocation(p, 1, "outA");
        glBindFragDataLocation(p, 0, "outB");
        if (inactive) {  // names this program does not have
          glBindAttribLocation(p, kTangent, "tangent");
          glBindFragDataLocation(p, 4, "outD");
          glBindFragDataLocation(p, 3, "outE");
        }
      });
  if (!prog) return 2;
  const std::pair<const char*, GLint> attributes[] = {
      {"pos", kPos}, {"color", kColor}, {"lay", kLay}, {"ints", kInts}, {"weight", kWeight}};
  for (const auto& [name, location] : attributes)
    if (glGetAttribLocation(prog, name) != location) {
      std::fprintf(stderr, "probe_attributes: %s is at %d, not %d\n", name, glGetAttribLocation(prog, name), location);
      return 2;
    }
  if (glGetFragDataLocation(prog, "outA") != 1 || glGetFragDataLocation(prog, "outB") != 0 ||
      glGetFragDataLocation(prog, "outC") != 2) {
    std::fprintf(stderr, "probe_attributes: outputs are not where they were bound\n");
    return 2;
  }

  GLuint vao = 0;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  static const float quad[] = {-1, -1, 1, -1, 1, 1, -1, -1, 1, 1, -1, 1};
  GLuint pos_buffer = 0;
  glGenBuffers(1, &pos_buffer);
  glBindBuffer(GL_ARRAY_BUFFER, pos_buffer);
  glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
  glVertexAttribPointer(kPos, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(kPos);
  Arrays arrays;
  glGenBuffers(1, &arrays.color);
  glBindBuffer(GL_ARRAY_BUFFER, arrays.color);
  glBufferData(GL_ARRAY_BUFFER, 6 * 4 * sizeof(float), nullptr, GL_DYNAMIC_DRAW);
  glVertexAttribPointer(kColor, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(kColor);
  glGenBuffers(1, &arrays.lay);
  glBindBuffer(GL_ARRAY_BUFFER, arrays.lay);
  glBufferData(GL_ARRAY_BUFFER, 6 * 3 * sizeof(float), nullptr, GL_DYNAMIC_DRAW);
  glVertexAttribPointer(kLay, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(kLay);
  glGenBuffers(1, &arrays.ints);
  glBindBuffer(GL_ARRAY_BUFFER, arrays.ints);
  glBufferData(GL_ARRAY_BUFFER, 6 * 2 * sizeof(int32_t), nullptr, GL_DYNAMIC_DRAW);
  glVertexAttribIPointer(kInts, 2, GL_INT, 0, nullptr);
  glEnableVertexAttribArray(kInts);
  if (inactive) {  // tangent: (0, 0, 0, 0) at every vertex
    const float zeros[6 * 4] = {};
    GLuint tangents = 0;
    glGenBuffers(1, &tangents);
    glBindBuffer(GL_ARRAY_BUFFER, tangents);
    glBufferData(GL_ARRAY_BUFFER, sizeof zeros, zeros, GL_STATIC_DRAW);
    glVertexAttribPointer(kTangent, 4, GL_FLOAT, GL_FALSE, 0, nullptr);
    glEnableVertexAttribArray(kTangent);
  }

  // Attachments 0, 1 (and 3, 4): GL_RGBA32F; 2: GL_RGBA32UI.
  const int attachments = inactive ? 5 : 3;
  GLuint fbo = 0, tex[5] = {};
  glGenFramebuffers(1, &fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  glGenTextures(attachments, tex);
  for (int i = 0; i < attachments; ++i) {
    glBindTexture(GL_TEXTURE_2D, tex[i]);
    glTexStorage2D(GL_TEXTURE_2D, 1, i == 2 ? GL_RGBA32UI : GL_RGBA32F, kSide, kSide);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(i), GL_TEXTURE_2D, tex[i], 0);
  }
  const GLenum draw_buffers[5] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2,
                                  GL_COLOR_ATTACHMENT3, GL_COLOR_ATTACHMENT4};
  glDrawBuffers(attachments, draw_buffers);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    std::fprintf(stderr, "probe_attributes: the framebuffer is incomplete\n");
    return 2;
  }
  glViewport(0, 0, kSide, kSide);
  probe.check_gl_error("after setup");

  auto draw_and_check = [&](int p) {
    const float clear_f[4] = {-1, -1, -1, -1};
    const GLuint clear_u[4] = {0xdead0000u, 0xdead0000u, 0xdead0000u, 0xdead0000u};
    glClearBufferfv(GL_COLOR, 0, clear_f);
    glClearBufferfv(GL_COLOR, 1, clear_f);
    glClearBufferuiv(GL_COLOR, 2, clear_u);
    if (inactive) {
      glClearBufferfv(GL_COLOR, 3, clear_f);
      glClearBufferfv(GL_COLOR, 4, clear_f);
    }
    glDrawArrays(GL_TRIANGLES, 0, 6);
    std::vector<float> a0(kSide * kSide * 4), a1(kSide * kSide * 4);
    std::vector<uint32_t> a2(kSide * kSide * 4);
    glReadBuffer(GL_COLOR_ATTACHMENT0);
    glReadPixels(0, 0, kSide, kSide, GL_RGBA, GL_FLOAT, a0.data());
    glReadBuffer(GL_COLOR_ATTACHMENT1);
    glReadPixels(0, 0, kSide, kSide, GL_RGBA, GL_FLOAT, a1.data());
    glReadBuffer(GL_COLOR_ATTACHMENT2);
    glReadPixels(0, 0, kSide, kSide, GL_RGBA_INTEGER, GL_UNSIGNED_INT, a2.data());
    report_mark(probe, a2, "phase " + std::to_string(p));
    for (int k = 3; inactive && a2[0] != 0 && k < 5; ++k) {
      // outE and outD exist only where VARIANT_MARK != 0, and must then be where the app bound them.
      std::vector<float> a(kSide * kSide * 4);
      glReadBuffer(GL_COLOR_ATTACHMENT0 + static_cast<GLenum>(k));
      glReadPixels(0, 0, kSide, kSide, GL_RGBA, GL_FLOAT, a.data());
      const float expected = k == 3 ? 43.0f : 42.0f;
      for (float v : a)
        if (v != expected) {
          probe.fail("attachment %d (out%c, bound there by the app): expected %g, got %g", k, k == 3 ? 'E' : 'D',
                     expected, v);
          break;
        }
    }
    const Values v = values(p);
    const float out_b[4] = {v.lay[0], v.lay[1], v.lay[2], v.weight};
    const uint32_t out_c_ints[2] = {static_cast<uint32_t>(v.ints[0]), static_cast<uint32_t>(v.ints[1])};
    for (int px = 0; px < kSide * kSide; ++px) {
      const size_t at = static_cast<size_t>(px) * 4;
      if (std::memcmp(&a0[at], out_b, 16) != 0)
        probe.fail("pixel %d of attachment 0 (outB = lay, weight): expected %g %g %g %g, got %g %g %g %g", px, out_b[0],
                   out_b[1], out_b[2], out_b[3], a0[at], a0[at + 1], a0[at + 2], a0[at + 3]);
      if (std::memcmp(&a1[at], v.color, 16) != 0)
        probe.fail("pixel %d of attachment 1 (outA = color): expected %g %g %g %g, got %g %g %g %g", px, v.color[0],
                   v.color[1], v.color[2], v.color[3], a1[at], a1[at + 1], a1[at + 2], a1[at + 3]);
      if (a2[at] != a2[0] || a2[at + 1] != 0x600du || std::memcmp(&a2[at + 2], out_c_ints, 8) != 0)
        probe.fail("pixel %d of attachment 2 (outC = mark, 0x600d, ints): expected %u 600d %d %d, got %u %x %d %d", px,
                   a2[0], v.ints[0], v.ints[1], a2[at], a2[at + 1], static_cast<int32_t>(a2[at + 2]),
                   static_cast<int32_t>(a2[at + 3]));
      if (probe.failures() > 12) break;
    }
    probe.next_draw();
  };

  auto set_values = [&](int p) {
    const Values v = values(p);
    fill(arrays.color, v.color);
    fill(arrays.lay, v.lay);
    fill(arrays.ints, v.ints);
    glVertexAttrib1f(kWeight, v.weight);
  };

  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    glUseProgram(prog);
    if (frame > 0) draw_and_check(frame - 1);
    set_values(frame);
    probe.check_gl_error("after setting attributes");
    draw_and_check(frame);
    probe.check_gl_error("after drawing");
    eglSwapBuffers(w.display, w.surface);
  }
  return finish_and_close(probe, w);
}
