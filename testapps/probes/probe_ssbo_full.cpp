// An app that uses every shader storage block its fragment stage allows. It is valid GL, but
// its instrumented version needs one block more than the driver offers, so the instrumented
// program cannot link: glbudget must relink it from the app's shaders and say so once.
// Draws a full-window quad whose colour sums one value from each block.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdio>
#include <string>
#include <vector>

#include "common/egl_setup.hpp"
#include "common/direct_gl.hpp"
#include "common/known_scene.hpp"

namespace {
std::string fragment_source(int blocks) {
  std::string s = "#version 430 core\nout vec4 frag;\n";
  for (int i = 0; i < blocks; ++i)
    s += "layout(std430, binding = " + std::to_string(i) + ") readonly buffer B" + std::to_string(i) +
         " { vec4 v; } b" + std::to_string(i) + ";\n";
  s += "void main() {\n  vec4 sum = vec4(0.0);\n";
  for (int i = 0; i < blocks; ++i) s += "  sum += b" + std::to_string(i) + ".v;\n";
  s += "  frag = sum;\n}\n";
  return s;
}

const char* const kVertex =
    "#version 430 core\n"
    "layout(location=0) in vec2 pos;\n"
    "void main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n";

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_ssbo_full", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  GLint blocks = 0;
  glGetIntegerv(GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS, &blocks);
  const std::string fs_source = fragment_source(blocks);
  GLuint vs = compile_shader(GL_VERTEX_SHADER, kVertex), fs = compile_shader(GL_FRAGMENT_SHADER, fs_source.c_str());
  GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!vs || !fs || !linked) {
    fprintf(stderr, "probe_ssbo_full: a program with %d fragment storage blocks does not build\n", blocks);
    return 2;
  }
  // Block i holds (i+1)/255 in red and a constant elsewhere: the sum is exact in 8 bits.
  std::vector<GLuint> buffers(static_cast<size_t>(blocks));
  glGenBuffers(blocks, buffers.data());
  for (GLint i = 0; i < blocks; ++i) {
    const float v[4] = {(i + 1) / 255.0f / float(blocks), 0.5f / float(blocks), 0.25f / float(blocks),
                        1.0f / float(blocks)};
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, static_cast<GLuint>(i), buffers[static_cast<size_t>(i)]);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof v, v, GL_STATIC_DRAW);
  }
  bind_fullscreen_quad(args.width, args.height);
  glUseProgram(program);
  std::vector<uint8_t> image = draw_quad_frames(args.frames, args.width, args.height, w.display, w.surface);
  eglMakeCurrent(w.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(w.display, w.context);
  eglTerminate(w.display);
  return write_ppm(args.out, image, args.width, args.height) ? 0 : 3;
}
