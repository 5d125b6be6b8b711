#include "draw_copy.hpp"

#include <array>
#include <initializer_list>
#include <vector>

#include "hook_table.hpp"
#include "messages.hpp"

namespace glbudget {

// X(member, type): the entry points a copy calls (GL 1.1's typed by gl.h's prototypes, which
// glext.h gives no pointer types), each resolved as "gl" #member: the driver's
// own, so that the copy's draw is never counted or redirected as the app's.
// clang-format off
#define GLBUDGET_DRAW_COPY_FUNCTIONS(X)                              \
  X(CreateShader, PFNGLCREATESHADERPROC)                             \
  X(ShaderSource, PFNGLSHADERSOURCEPROC)                             \
  X(CompileShader, PFNGLCOMPILESHADERPROC)                           \
  X(GetShaderiv, PFNGLGETSHADERIVPROC)                               \
  X(DeleteShader, PFNGLDELETESHADERPROC)                             \
  X(CreateProgram, PFNGLCREATEPROGRAMPROC)                           \
  X(AttachShader, PFNGLATTACHSHADERPROC)                             \
  X(BindAttribLocation, PFNGLBINDATTRIBLOCATIONPROC)                 \
  X(LinkProgram, PFNGLLINKPROGRAMPROC)                               \
  X(GetProgramiv, PFNGLGETPROGRAMIVPROC)                             \
  X(DeleteProgram, PFNGLDELETEPROGRAMPROC)                           \
  X(UseProgram, PFNGLUSEPROGRAMPROC)                                 \
  X(GetUniformLocation, PFNGLGETUNIFORMLOCATIONPROC)                 \
  X(Uniform1i, PFNGLUNIFORM1IPROC)                                   \
  X(GenBuffers, PFNGLGENBUFFERSPROC)                                 \
  X(BindBuffer, PFNGLBINDBUFFERPROC)                                 \
  X(BufferData, PFNGLBUFFERDATAPROC)                                 \
  X(VertexAttribPointer, PFNGLVERTEXATTRIBPOINTERPROC)               \
  X(EnableVertexAttribArray, PFNGLENABLEVERTEXATTRIBARRAYPROC)       \
  X(DisableVertexAttribArray, PFNGLDISABLEVERTEXATTRIBARRAYPROC)     \
  X(GetVertexAttribiv, PFNGLGETVERTEXATTRIBIVPROC)                   \
  X(GetVertexAttribPointerv, PFNGLGETVERTEXATTRIBPOINTERVPROC)       \
  X(BindFramebuffer, PFNGLBINDFRAMEBUFFERPROC)                       \
  X(ActiveTexture, PFNGLACTIVETEXTUREPROC)                           \
  X(BindTexture, decltype(&::glBindTexture))                               \
  X(DrawArrays, decltype(&::glDrawArrays))                                 \
  X(GetIntegerv, decltype(&::glGetIntegerv))                               \
  X(GetBooleanv, decltype(&::glGetBooleanv))                               \
  X(Enable, decltype(&::glEnable))                                         \
  X(Disable, decltype(&::glDisable))                                       \
  X(IsEnabled, decltype(&::glIsEnabled))                                   \
  X(Viewport, decltype(&::glViewport))                                     \
  X(ColorMask, decltype(&::glColorMask))
// clang-format on

struct DrawCopy::Gl {
#define GLBUDGET_MEMBER(name, type) type name = nullptr;
  GLBUDGET_DRAW_COPY_FUNCTIONS(GLBUDGET_MEMBER)
#undef GLBUDGET_MEMBER
  bool load() {
    bool all = true;
#define GLBUDGET_LOAD(name, type)                        \
  name = reinterpret_cast<type>(resolve_gl("gl" #name)); \
  all = all && name != nullptr;
    GLBUDGET_DRAW_COPY_FUNCTIONS(GLBUDGET_LOAD)
#undef GLBUDGET_LOAD
    return all;
  }
};

namespace {
// GLSL ES 1.00 and GLSL 1.10: what every context without blits compiles. The varying goes to
// texture2D untouched, so that a mediump-only fragment stage (Mali-400) still addresses every
// texel of a wide window.
constexpr const char* kVertex =
    "attribute vec2 glbudget_corner;\n"
    "varying vec2 glbudget_uv;\n"
    "void main() {\n"
    "  glbudget_uv = glbudget_corner * 0.5 + 0.5;\n"
    "  gl_Position = vec4(glbudget_corner, 0.0, 1.0);\n"
    "}\n";
constexpr const char* kFragment =
    "uniform sampler2D glbudget_image;\n"
    "varying vec2 glbudget_uv;\n"
    "void main() { gl_FragColor = texture2D(glbudget_image, glbudget_uv); }\n";
// What each stage starts with: GLSL ES 1.00 has no #version line and wants a float precision in
// the fragment stage; desktop GL 2's GLSL is named.
constexpr const char* kEsFragmentPrecision = "precision mediump float;\n";
constexpr const char* kDesktopVersion = "#version 110\n";

// The switches that would change a copied pixel, turned off for the copy.
constexpr std::array<GLenum, 9> kSwitchesOff = {
    GL_BLEND,          GL_CULL_FACE, GL_DEPTH_TEST,          GL_STENCIL_TEST,
    GL_SCISSOR_TEST,   GL_DITHER,    GL_POLYGON_OFFSET_FILL, GL_SAMPLE_ALPHA_TO_COVERAGE,
    GL_SAMPLE_COVERAGE};
// And in desktop GL 2's fixed-function stages, which still act behind a fragment shader.
constexpr std::array<GLenum, 2> kDesktopSwitchesOff = {GL_ALPHA_TEST, GL_COLOR_LOGIC_OP};
}  // namespace

DrawCopy::DrawCopy(bool gles) : gl_(std::make_unique<Gl>()), gles_(gles) {}

// The context may be gone when its scaler is: its objects go with it.
DrawCopy::~DrawCopy() = default;

bool DrawCopy::ready() {
  if (tried_) return program_ != 0;
  tried_ = true;
  Gl& g = *gl_;
  if (!g.load()) {
    say_once("draw-copy", "the driver lacks an entry point a drawn copy needs: the window is not scaled");
    return false;
  }
  auto compile = [&](GLenum stage, std::initializer_list<const char*> parts) -> GLuint {
    const GLuint shader = g.CreateShader(stage);
    const std::vector<const char*> sources(parts);
    g.ShaderSource(shader, static_cast<GLsizei>(sources.size()), sources.data(), nullptr);
    g.CompileShader(shader);
    GLint ok = GL_FALSE;
    g.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (ok) return shader;
    g.DeleteShader(shader);
    return 0;
  };
  const GLuint vs = compile(GL_VERTEX_SHADER, {gles_ ? "" : kDesktopVersion, kVertex});
  const GLuint fs = compile(GL_FRAGMENT_SHADER, {gles_ ? kEsFragmentPrecision : kDesktopVersion, kFragment});
  if (vs && fs) {
    program_ = g.CreateProgram();
    g.AttachShader(program_, vs);
    g.AttachShader(program_, fs);
    g.BindAttribLocation(program_, 0, "glbudget_corner");
    g.LinkProgram(program_);
    GLint linked = GL_FALSE;
    g.GetProgramiv(program_, GL_LINK_STATUS, &linked);
    if (!linked) {
      g.DeleteProgram(program_);
      program_ = 0;
    }
  }
  if (vs) g.DeleteShader(vs);
  if (fs) g.DeleteShader(fs);
  if (!program_) {
    say_once("draw-copy", "the driver did not build the window's copy program: the window is not scaled");
    return false;
  }
  sampler_ = g.GetUniformLocation(program_, "glbudget_image");
  GLint array_buffer = 0;
  g.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer);
  g.GenBuffers(1, &buffer_);
  g.BindBuffer(GL_ARRAY_BUFFER, buffer_);
  static constexpr GLfloat kCorners[] = {-1, -1, 1, -1, -1, 1, 1, 1};  // a strip over the whole target
  g.BufferData(GL_ARRAY_BUFFER, sizeof kCorners, kCorners, GL_STATIC_DRAW);
  g.BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer));
  return true;
}

bool DrawCopy::copy(GLuint from, GLuint to, int width, int height) {
  if (!ready()) return false;
  Gl& g = *gl_;
  // What is changed below, as the app left it.
  GLint framebuffer = 0, viewport[4] = {}, program = 0, active = GL_TEXTURE0, texture = 0, array_buffer = 0;
  GLboolean mask[4] = {GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE};
  GLint attrib_enabled = 0, attrib_size = 4, attrib_type = GL_FLOAT, attrib_normalized = 0, attrib_stride = 0,
        attrib_buffer = 0;
  void* attrib_pointer = nullptr;
  g.GetIntegerv(GL_FRAMEBUFFER_BINDING, &framebuffer);
  g.GetIntegerv(GL_VIEWPORT, viewport);
  g.GetIntegerv(GL_CURRENT_PROGRAM, &program);
  g.GetIntegerv(GL_ACTIVE_TEXTURE, &active);
  g.ActiveTexture(GL_TEXTURE0);
  g.GetIntegerv(GL_TEXTURE_BINDING_2D, &texture);
  g.GetIntegerv(GL_ARRAY_BUFFER_BINDING, &array_buffer);
  g.GetBooleanv(GL_COLOR_WRITEMASK, mask);
  g.GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_ENABLED, &attrib_enabled);
  g.GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_SIZE, &attrib_size);
  g.GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_TYPE, &attrib_type);
  g.GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_NORMALIZED, &attrib_normalized);
  g.GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_STRIDE, &attrib_stride);
  g.GetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &attrib_buffer);
  g.GetVertexAttribPointerv(0, GL_VERTEX_ATTRIB_ARRAY_POINTER, &attrib_pointer);
  std::array<bool, kSwitchesOff.size() + kDesktopSwitchesOff.size()> was_on{};
  size_t i = 0;
  auto turn_off = [&](GLenum cap) {
    was_on[i] = g.IsEnabled(cap) == GL_TRUE;
    if (was_on[i]) g.Disable(cap);
    ++i;
  };
  for (GLenum cap : kSwitchesOff) turn_off(cap);
  if (!gles_)
    for (GLenum cap : kDesktopSwitchesOff) turn_off(cap);

  g.BindFramebuffer(GL_FRAMEBUFFER, to);
  g.Viewport(0, 0, width, height);
  g.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  g.UseProgram(program_);
  g.Uniform1i(sampler_, 0);
  g.BindTexture(GL_TEXTURE_2D, from);
  g.BindBuffer(GL_ARRAY_BUFFER, buffer_);
  g.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  g.EnableVertexAttribArray(0);
  g.DrawArrays(GL_TRIANGLE_STRIP, 0, 4);

  g.BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(attrib_buffer));
  g.VertexAttribPointer(0, attrib_size, static_cast<GLenum>(attrib_type), static_cast<GLboolean>(attrib_normalized),
                        attrib_stride, attrib_pointer);
  if (!attrib_enabled) g.DisableVertexAttribArray(0);
  g.BindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(array_buffer));
  g.BindTexture(GL_TEXTURE_2D, static_cast<GLuint>(texture));
  g.ActiveTexture(static_cast<GLenum>(active));
  g.UseProgram(static_cast<GLuint>(program));
  g.ColorMask(mask[0], mask[1], mask[2], mask[3]);
  g.Viewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  g.BindFramebuffer(GL_FRAMEBUFFER, static_cast<GLuint>(framebuffer));
  i = 0;
  auto restore = [&](GLenum cap) {
    if (was_on[i++]) g.Enable(cap);
  };
  for (GLenum cap : kSwitchesOff) restore(cap);
  if (!gles_)
    for (GLenum cap : kDesktopSwitchesOff) restore(cap);
  return true;
}

}  // namespace glbudget
