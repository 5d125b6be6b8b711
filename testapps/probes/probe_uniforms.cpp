// Uniforms of every type reach the program that draws (issue 12, shadowing case 1): float, int,
// uint, bool and double scalars and vectors, every float and several double matrices (square
// and not), arrays of basic types, structs, arrays of structs and a struct in a struct, plus
// two uniforms with initialisers the app never sets (and location -1, set every frame, which GL
// ignores). The fragment shader writes every component into its own slot of a GL_RGBA32UI
// target (see probe_shadowing.hpp), so each read-back is the exact bits the driver's bound
// program saw. (Subroutine uniforms: probe_subroutines.)
//
// Each frame: glUseProgram; from frame 1 on a draw that must still show the previous frame's
// values (they were set before the swap, where glbudget may switch to another variant); then
// new values, set a different way each frame, and a draw that must show them:
//   frame % 2:        0: glUniform* (the bound program), 1: glProgramUniform*
//   (frame / 2) % 3:  arrays 0: one call for all elements, 1: element by element at `loc + i`,
//                     2: element 0, then the rest in one call at `loc + 1`
//   per uniform:      scalar-argument forms (glUniform3f) or vector forms (glUniform3fv)
//   frame % 4 == 3:   matrices transposed (GL_TRUE, row-major data)
//   bools:            by frame % 3 through the int, float and uint setters
// The shader's source holds "PROBE_UNIFORMS" (for a manifest to match) and `#define
// VARIANT_MARK 0`, which slot 0 reports; with VARIANT_MARK != 0 it declares three more uniforms
// ahead of the others (so a variant's locations differ from the app's: by 5 on Mesa). They
// take 32 components, a multiple of four: llvmpipe (Mesa 22) was seen reading a double that is a
// struct member one word early when the components ahead of it are not (a driver bug, with or
// without glbudget).
#define GL_GLEXT_PROTOTYPES 1
#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

#include "probe_shadowing.hpp"

using namespace shadow_probe;

namespace {

enum class B { f, i, u, b, d };

struct Type {
  const char* glsl;
  B base;
  int cols, rows;  // scalar 1x1, vecN 1xN, matCxR
};

struct Leaf {
  std::string name;  // a GLSL expression: "u_v3", "u_sa[1].b", "u_t.inner.c"
  Type type;
  int elements = 1;     // > 1: an array of basic type
  bool declare = true;  // false: a member of a struct declared by hand
};

const Type kFloat{"float", B::f, 1, 1}, kVec2{"vec2", B::f, 1, 2}, kVec3{"vec3", B::f, 1, 3}, kVec4{"vec4", B::f, 1, 4};
const Type kInt{"int", B::i, 1, 1}, kIvec2{"ivec2", B::i, 1, 2}, kIvec3{"ivec3", B::i, 1, 3},
    kIvec4{"ivec4", B::i, 1, 4};
const Type kUint{"uint", B::u, 1, 1}, kUvec2{"uvec2", B::u, 1, 2}, kUvec3{"uvec3", B::u, 1, 3},
    kUvec4{"uvec4", B::u, 1, 4};
const Type kBool{"bool", B::b, 1, 1}, kBvec2{"bvec2", B::b, 1, 2}, kBvec3{"bvec3", B::b, 1, 3},
    kBvec4{"bvec4", B::b, 1, 4};
const Type kDouble{"double", B::d, 1, 1}, kDvec2{"dvec2", B::d, 1, 2}, kDvec3{"dvec3", B::d, 1, 3},
    kDvec4{"dvec4", B::d, 1, 4};

std::vector<Leaf> leaves() {
  std::vector<Leaf> l = {{"u_f", kFloat},
                         {"u_v2", kVec2},
                         {"u_v3", kVec3},
                         {"u_v4", kVec4},
                         {"u_i", kInt},
                         {"u_iv2", kIvec2},
                         {"u_iv3", kIvec3},
                         {"u_iv4", kIvec4},
                         {"u_u", kUint},
                         {"u_uv2", kUvec2},
                         {"u_uv3", kUvec3},
                         {"u_uv4", kUvec4},
                         {"u_b", kBool},
                         {"u_bv2", kBvec2},
                         {"u_bv3", kBvec3},
                         {"u_bv4", kBvec4},
                         {"u_m2", {"mat2", B::f, 2, 2}},
                         {"u_m3", {"mat3", B::f, 3, 3}},
                         {"u_m4", {"mat4", B::f, 4, 4}},
                         {"u_m2x3", {"mat2x3", B::f, 2, 3}},
                         {"u_m2x4", {"mat2x4", B::f, 2, 4}},
                         {"u_m3x2", {"mat3x2", B::f, 3, 2}},
                         {"u_m3x4", {"mat3x4", B::f, 3, 4}},
                         {"u_m4x2", {"mat4x2", B::f, 4, 2}},
                         {"u_m4x3", {"mat4x3", B::f, 4, 3}},
                         {"u_d", kDouble},
                         {"u_dv2", kDvec2},
                         {"u_dv3", kDvec3},
                         {"u_dv4", kDvec4},
                         {"u_dm2", {"dmat2", B::d, 2, 2}},
                         {"u_dm3", {"dmat3", B::d, 3, 3}},
                         {"u_dm4", {"dmat4", B::d, 4, 4}},
                         {"u_dm2x3", {"dmat2x3", B::d, 2, 3}},
                         {"u_dm3x2", {"dmat3x2", B::d, 3, 2}},
                         {"u_dm4x2", {"dmat4x2", B::d, 4, 2}},
                         {"u_fa", kFloat, 4},
                         {"u_v3a", kVec3, 3},
                         {"u_ia", kInt, 5},
                         {"u_uv2a", kUvec2, 2},
                         {"u_ba", kBool, 3},
                         {"u_m2a", {"mat2", B::f, 2, 2}, 2},
                         {"u_m3x2a", {"mat3x2", B::f, 3, 2}, 2},
                         {"u_dv2a", kDvec2, 2}};
  // struct S { float a; vec3 b; int c[2]; mat2x3 m; bool f; uvec2 g; };
  auto s_members = [&l](const std::string& prefix) {
    l.push_back({prefix + ".a", kFloat, 1, false});
    l.push_back({prefix + ".b", kVec3, 1, false});
    l.push_back({prefix + ".c", kInt, 2, false});
    l.push_back({prefix + ".m", {"mat2x3", B::f, 2, 3}, 1, false});
    l.push_back({prefix + ".f", kBool, 1, false});
    l.push_back({prefix + ".g", kUvec2, 1, false});
  };
  s_members("u_s");
  for (int i = 0; i < 3; ++i) s_members("u_sa[" + std::to_string(i) + "]");
  // struct T { S inner; uvec3 t; dvec3 d; };
  s_members("u_t.inner");
  l.push_back({"u_t.t", kUvec3, 1, false});
  l.push_back({"u_t.d", kDvec3, 1, false});
  return l;
}

const char* const kStructs =
    "struct S { float a; vec3 b; int c[2]; mat2x3 m; bool f; uvec2 g; };\n"
    "struct T { S inner; uvec3 t; dvec3 d; };\n"
    "uniform S u_s;\n"
    "uniform S u_sa[3];\n"
    "uniform T u_t;\n"
    "uniform float u_init = 2.5;\n"
    "uniform ivec2 u_init2 = ivec2(-3, 9);\n"
    "uniform vec4 u_dead;  // never read: no location\n";

// One slot of the target: which leaf, element, column and (doubles with 3-4 rows) half.
struct Slot {
  size_t leaf;
  int element, column, half;
  std::string glsl;
};

std::vector<Slot> slots(const std::vector<Leaf>& all) {
  std::vector<Slot> out;
  for (size_t li = 0; li < all.size(); ++li) {
    const Leaf& l = all[li];
    for (int e = 0; e < l.elements; ++e) {
      const std::string elem = l.elements > 1 ? l.name + "[" + std::to_string(e) + "]" : l.name;
      for (int c = 0; c < l.type.cols; ++c) {
        const std::string col = l.type.cols > 1 ? elem + "[" + std::to_string(c) + "]" : elem;
        if (l.type.base == B::d && l.type.rows > 2) {
          out.push_back({li, e, c, 0, "enc(" + col + ".xy)"});
          out.push_back({li, e, c, 1, "enc(" + col + (l.type.rows == 3 ? ".z)" : ".zw)")});
        } else {
          out.push_back({li, e, c, 0, "enc(" + col + ")"});
        }
      }
    }
  }
  return out;
}

constexpr int kSide = 16;  // 256 slots
const GLfloat kFilter4[4] = {9, 9, 9, 9};

std::string fragment_source(const std::vector<Leaf>& all, const std::vector<Slot>& table) {
  std::string s =
      "#version 450 core\n"
      "// PROBE_UNIFORMS: every type of uniform, encoded bit for bit\n"
      "#define VARIANT_MARK 0\n"
      "#if VARIANT_MARK\n"
      "uniform vec4 a_shift0;\n"
      "uniform vec4 a_shift1[3];\n"
      "uniform mat4 a_shift2;\n"
      "#define MARK_SHIFT uint(a_shift0.w + a_shift1[2].w + a_shift2[3][3])\n"
      "#else\n"
      "#define MARK_SHIFT 0u\n"
      "#endif\n";
  s += kStructs;
  for (const Leaf& l : all) {
    if (!l.declare) continue;
    s += std::string("uniform ") + l.type.glsl + " " + l.name;
    if (l.elements > 1) s += "[" + std::to_string(l.elements) + "]";
    s += ";\n";
  }
  s += "out uvec4 o;\n";
  s += glsl_encoders(true);
  std::vector<std::string> cases = {"uvec4(uint(VARIANT_MARK) + MARK_SHIFT, 0x600du, 0u, 0u)",
                                    "uvec4(floatBitsToUint(u_init), uvec2(u_init2), 0u)"};
  for (const Slot& slot : table) cases.push_back(slot.glsl);
  s += glsl_slot_function(cases);
  s += "void main() { ivec2 p = ivec2(gl_FragCoord.xy); o = slot(p.y * " + std::to_string(kSide) + " + p.x); }\n";
  return s;
}

// The value of component `c` (column-major) of element `e` of leaf `li` in phase `p`.
float value_f(int p, size_t li, int e, int c) {
  const float v = static_cast<float>(p + 1) * 0.5f + static_cast<float>(li) * 1.25f + static_cast<float>(e) * 0.125f +
                  static_cast<float>(c) * 0.015625f;
  return li % 2 ? -v : v;
}
int32_t value_i(int p, size_t li, int e, int c) {
  return (static_cast<int32_t>(li) * 64 + e * 8 + c + 1) * (p % 2 ? -1 : 1) - p * 100000;
}
uint32_t value_u(int p, size_t li, int e, int c) {
  return 0x80000000u + static_cast<uint32_t>(li) * 4096u + static_cast<uint32_t>(e) * 64u + static_cast<uint32_t>(c) +
         static_cast<uint32_t>(p) * 0x1000000u;
}
bool value_b(int p, size_t li, int e, int c) { return (li + static_cast<size_t>(e + c + p)) % 2 == 1; }
double value_d(int p, size_t li, int e, int c) {
  return (p + 1) * 0.25 + static_cast<double>(li) * 3.0 + e * 0.5 + c / 1024.0 + 1e-9 * static_cast<double>(li + 1);
}

// The four words a slot must hold in phase `p`.
void expected_slot(const Leaf& l, const Slot& s, int p, uint32_t out[4]) {
  out[0] = out[1] = out[2] = out[3] = 0;
  const int rows = l.type.rows;
  if (l.type.base == B::d) {
    const int first = s.half * 2, n = std::min(2, rows - first);
    for (int r = 0; r < n; ++r)
      double_words(value_d(p, s.leaf, s.element, s.column * rows + first + r), &out[2 * r], &out[2 * r + 1]);
    return;
  }
  for (int r = 0; r < rows; ++r) {
    const int c = s.column * rows + r;
    switch (l.type.base) {
      case B::f:
        out[r] = float_bits(value_f(p, s.leaf, s.element, c));
        break;
      case B::i:
        out[r] = static_cast<uint32_t>(value_i(p, s.leaf, s.element, c));
        break;
      case B::u:
        out[r] = value_u(p, s.leaf, s.element, c);
        break;
      case B::b:
        out[r] = value_b(p, s.leaf, s.element, c) ? 1u : 0u;
        break;
      case B::d:
        break;
    }
  }
}

// Calls the vector setter of `n` components of base `call` (f, i, u or d): scalar arguments
// (count 1) or the v form, glUniform* or glProgramUniform*.
void set_vector(B call, int n, bool dsa, bool scalar_args, GLuint prog, GLint loc, GLsizei count, const void* data) {
#define PROBE_VEC(SUF, T)                                                                                     \
  {                                                                                                           \
    const T* v = static_cast<const T*>(data);                                                                 \
    switch (n) {                                                                                              \
      case 1:                                                                                                 \
        if (scalar_args)                                                                                      \
          dsa ? glProgramUniform1##SUF(prog, loc, v[0]) : glUniform1##SUF(loc, v[0]);                         \
        else                                                                                                  \
          dsa ? glProgramUniform1##SUF##v(prog, loc, count, v) : glUniform1##SUF##v(loc, count, v);           \
        return;                                                                                               \
      case 2:                                                                                                 \
        if (scalar_args)                                                                                      \
          dsa ? glProgramUniform2##SUF(prog, loc, v[0], v[1]) : glUniform2##SUF(loc, v[0], v[1]);             \
        else                                                                                                  \
          dsa ? glProgramUniform2##SUF##v(prog, loc, count, v) : glUniform2##SUF##v(loc, count, v);           \
        return;                                                                                               \
      case 3:                                                                                                 \
        if (scalar_args)                                                                                      \
          dsa ? glProgramUniform3##SUF(prog, loc, v[0], v[1], v[2]) : glUniform3##SUF(loc, v[0], v[1], v[2]); \
        else                                                                                                  \
          dsa ? glProgramUniform3##SUF##v(prog, loc, count, v) : glUniform3##SUF##v(loc, count, v);           \
        return;                                                                                               \
      default:                                                                                                \
        if (scalar_args)                                                                                      \
          dsa ? glProgramUniform4##SUF(prog, loc, v[0], v[1], v[2], v[3])                                     \
              : glUniform4##SUF(loc, v[0], v[1], v[2], v[3]);                                                 \
        else                                                                                                  \
          dsa ? glProgramUniform4##SUF##v(prog, loc, count, v) : glUniform4##SUF##v(loc, count, v);           \
        return;                                                                                               \
    }                                                                                                         \
  }
  switch (call) {
    case B::f:
      PROBE_VEC(f, GLfloat)
    case B::i:
      PROBE_VEC(i, GLint)
    case B::u:
      PROBE_VEC(ui, GLuint)
    case B::d:
      PROBE_VEC(d, GLdouble)
    case B::b:
      return;
  }
#undef PROBE_VEC
}

void set_matrix_f(int cols, int rows, bool dsa, GLuint prog, GLint loc, GLsizei count, GLboolean transpose,
                  const GLfloat* v) {
  using Plain = void (*)(GLint, GLsizei, GLboolean, const GLfloat*);
  using Dsa = void (*)(GLuint, GLint, GLsizei, GLboolean, const GLfloat*);
  Plain plain = nullptr;
  Dsa program = nullptr;
  switch (cols * 10 + rows) {
    case 22:
      plain = glUniformMatrix2fv;
      program = glProgramUniformMatrix2fv;
      break;
    case 33:
      plain = glUniformMatrix3fv;
      program = glProgramUniformMatrix3fv;
      break;
    case 44:
      plain = glUniformMatrix4fv;
      program = glProgramUniformMatrix4fv;
      break;
    case 23:
      plain = glUniformMatrix2x3fv;
      program = glProgramUniformMatrix2x3fv;
      break;
    case 24:
      plain = glUniformMatrix2x4fv;
      program = glProgramUniformMatrix2x4fv;
      break;
    case 32:
      plain = glUniformMatrix3x2fv;
      program = glProgramUniformMatrix3x2fv;
      break;
    case 34:
      plain = glUniformMatrix3x4fv;
      program = glProgramUniformMatrix3x4fv;
      break;
    case 42:
      plain = glUniformMatrix4x2fv;
      program = glProgramUniformMatrix4x2fv;
      break;
    case 43:
      plain = glUniformMatrix4x3fv;
      program = glProgramUniformMatrix4x3fv;
      break;
  }
  if (dsa)
    program(prog, loc, count, transpose, v);
  else
    plain(loc, count, transpose, v);
}

void set_matrix_d(int cols, int rows, bool dsa, GLuint prog, GLint loc, GLsizei count, GLboolean transpose,
                  const GLdouble* v) {
  using Plain = void (*)(GLint, GLsizei, GLboolean, const GLdouble*);
  using Dsa = void (*)(GLuint, GLint, GLsizei, GLboolean, const GLdouble*);
  Plain plain = nullptr;
  Dsa program = nullptr;
  switch (cols * 10 + rows) {
    case 22:
      plain = glUniformMatrix2dv;
      program = glProgramUniformMatrix2dv;
      break;
    case 33:
      plain = glUniformMatrix3dv;
      program = glProgramUniformMatrix3dv;
      break;
    case 44:
      plain = glUniformMatrix4dv;
      program = glProgramUniformMatrix4dv;
      break;
    case 23:
      plain = glUniformMatrix2x3dv;
      program = glProgramUniformMatrix2x3dv;
      break;
    case 24:
      plain = glUniformMatrix2x4dv;
      program = glProgramUniformMatrix2x4dv;
      break;
    case 32:
      plain = glUniformMatrix3x2dv;
      program = glProgramUniformMatrix3x2dv;
      break;
    case 34:
      plain = glUniformMatrix3x4dv;
      program = glProgramUniformMatrix3x4dv;
      break;
    case 42:
      plain = glUniformMatrix4x2dv;
      program = glProgramUniformMatrix4x2dv;
      break;
    case 43:
      plain = glUniformMatrix4x3dv;
      program = glProgramUniformMatrix4x3dv;
      break;
  }
  if (dsa)
    program(prog, loc, count, transpose, v);
  else
    plain(loc, count, transpose, v);
}

// Sets elements [e0, e0 + count) of leaf `li` at `loc` to their phase-`p` values.
void set_elements(const Leaf& l, size_t li, GLuint prog, GLint loc, int e0, int count, int p) {
  const bool dsa = p % 2 == 1;
  const bool scalar_args = count == 1 && l.type.cols == 1 && (li + static_cast<size_t>(p)) % 2 == 0;
  const bool transpose = p % 4 == 3;
  const int cols = l.type.cols, rows = l.type.rows, per = cols * rows;
  // Component k of the data passed: column-major, or row-major when transposed.
  auto source_component = [&](int k) {
    if (!transpose || cols == 1) return k;
    const int r = k / cols, c = k % cols;  // row-major index k = r * cols + c
    return c * rows + r;
  };
  std::vector<GLfloat> f;
  std::vector<GLint> i;
  std::vector<GLuint> u;
  std::vector<GLdouble> d;
  for (int e = e0; e < e0 + count; ++e)
    for (int k = 0; k < per; ++k) {
      const int c = source_component(k);
      switch (l.type.base) {
        case B::f:
          f.push_back(value_f(p, li, e, c));
          break;
        case B::i:
          i.push_back(value_i(p, li, e, c));
          break;
        case B::u:
          u.push_back(value_u(p, li, e, c));
          break;
        case B::d:
          d.push_back(value_d(p, li, e, c));
          break;
        case B::b: {
          const bool b = value_b(p, li, e, c);
          // Any non-zero value is true, whichever setter.
          i.push_back(b ? 7 + c : 0);
          f.push_back(b ? 0.75f : 0.0f);
          u.push_back(b ? 0x80000000u + static_cast<uint32_t>(c) : 0u);
          break;
        }
      }
    }
  if (cols > 1) {
    const GLboolean t = transpose ? GL_TRUE : GL_FALSE;
    if (l.type.base == B::f)
      set_matrix_f(cols, rows, dsa, prog, loc, count, t, f.data());
    else
      set_matrix_d(cols, rows, dsa, prog, loc, count, t, d.data());
    return;
  }
  switch (l.type.base) {
    case B::f:
      return set_vector(B::f, rows, dsa, scalar_args, prog, loc, count, f.data());
    case B::i:
      return set_vector(B::i, rows, dsa, scalar_args, prog, loc, count, i.data());
    case B::u:
      return set_vector(B::u, rows, dsa, scalar_args, prog, loc, count, u.data());
    case B::d:
      return set_vector(B::d, rows, dsa, scalar_args, prog, loc, count, d.data());
    case B::b:
      switch (p % 3) {
        case 0:
          return set_vector(B::i, rows, dsa, scalar_args, prog, loc, count, i.data());
        case 1:
          return set_vector(B::f, rows, dsa, scalar_args, prog, loc, count, f.data());
        default:
          return set_vector(B::u, rows, dsa, scalar_args, prog, loc, count, u.data());
      }
  }
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Probe probe("probe_uniforms");
  EglFns egl;
  EglWindow w;
  if (!open_current_window(probe.name(), egl, ContextKind::kCore45, kSide, kSide, &w)) return 2;
  const std::vector<Leaf> all = leaves();
  const std::vector<Slot> table = slots(all);
  if (table.size() + 2 > static_cast<size_t>(kSide * kSide)) {
    std::fprintf(stderr, "probe_uniforms: %zu slots do not fit\n", table.size());
    return 2;
  }
  const GLuint prog = build_program(
      probe.name(), {{GL_VERTEX_SHADER, quad_vertex_shader()}, {GL_FRAGMENT_SHADER, fragment_source(all, table)}});
  if (!prog) return 2;
  // The app's locations: element 0 of each leaf, and arrays' elements at loc + i (checked).
  std::vector<GLint> loc(all.size(), -1);
  for (size_t li = 0; li < all.size(); ++li) {
    loc[li] = glGetUniformLocation(prog, all[li].name.c_str());
    if (loc[li] < 0) {
      std::fprintf(stderr, "probe_uniforms: no location for %s\n", all[li].name.c_str());
      return 2;
    }
    for (int e = 1; e < all[li].elements; ++e) {
      const std::string name = all[li].name + "[" + std::to_string(e) + "]";
      if (glGetUniformLocation(prog, name.c_str()) != loc[li] + e) {
        std::fprintf(stderr, "probe_uniforms: %s is not at %s's location + %d\n", name.c_str(), all[li].name.c_str(),
                     e);
        return 2;
      }
    }
  }
  bind_fullscreen_quad(kSide, kSide);
  SlotTarget target;
  if (!target.create(kSide, kSide)) {
    std::fprintf(stderr, "probe_uniforms: the GL_RGBA32UI framebuffer is incomplete\n");
    return 2;
  }
  probe.check_gl_error("after setup");

  auto draw_and_check = [&](int p) {
    const std::vector<uint32_t> words = target.draw_and_read();
    report_mark(probe, words, "phase " + std::to_string(p));
    const uint32_t init[4] = {float_bits(2.5f), static_cast<uint32_t>(-3), 9u, 0u};
    expect_slot(probe, words, 1, init, "u_init, u_init2 (initialisers)");
    for (size_t i = 0; i < table.size(); ++i) {
      const Slot& s = table[i];
      uint32_t expected[4];
      expected_slot(all[s.leaf], s, p, expected);
      std::string what = all[s.leaf].name;
      if (all[s.leaf].elements > 1) what += "[" + std::to_string(s.element) + "]";
      if (all[s.leaf].type.cols > 1) what += " column " + std::to_string(s.column);
      if (s.half) what += " (second half)";
      what += " phase " + std::to_string(p);
      expect_slot(probe, words, static_cast<int>(i) + 2, expected, what);
    }
    probe.next_draw();
  };

  for (int frame = 0; frame < args.frames; ++frame) {
    probe.set_frame(frame);
    glUseProgram(prog);
    if (frame > 0) draw_and_check(frame - 1);  // the values set before the swap
    const int array_mode = (frame / 2) % 3;
    for (size_t li = 0; li < all.size(); ++li) {
      const Leaf& l = all[li];
      if (l.elements == 1 || array_mode == 0) {
        set_elements(l, li, prog, loc[li], 0, l.elements, frame);
      } else if (array_mode == 1) {
        for (int e = 0; e < l.elements; ++e) set_elements(l, li, prog, loc[li] + e, e, 1, frame);
      } else {
        set_elements(l, li, prog, loc[li], 0, 1, frame);
        set_elements(l, li, prog, loc[li] + 1, 1, l.elements - 1, frame);
      }
    }
    // Location -1 (an unknown name, a uniform the compiler dropped) is ignored silently.
    glUniform1f(glGetUniformLocation(prog, "u_dead"), 1.0f);
    glUniform4fv(-1, 1, kFilter4);
    glProgramUniform1i(prog, -1, 3);
    glProgramUniformMatrix2fv(prog, glGetUniformLocation(prog, "no_such_uniform"), 1, GL_FALSE, kFilter4);
    probe.check_gl_error("after setting uniforms");
    draw_and_check(frame);
    probe.check_gl_error("after drawing");
    swap_window(w);
  }
  return finish_and_close(probe, w);
}
