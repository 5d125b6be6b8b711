// Separable programs in a program pipeline: one program for the vertex stage and one for the
// fragment stage (both built with glLinkProgram), drawing a full-window quad. Hand counts:
//   vertex program:   gl_Position = vec4(pos, 0.0, 1.0)   2 instructions per vertex
//   fragment program: frag = color * 0.5                   2 instructions per fragment
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdio>
#include <vector>

#include "common/egl_setup.hpp"
#include "common/direct_gl.hpp"
#include "common/known_scene.hpp"

namespace {
const char* const kVertex =
    "#version 430 core\n"
    "layout(location=0) in vec2 pos;\n"
    "out gl_PerVertex { vec4 gl_Position; };\n"
    "void main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n";
const char* const kFragment =
    "#version 430 core\n"
    "uniform vec4 color;\n"
    "out vec4 frag;\n"
    "void main(){ frag = color * 0.5; }\n";

GLuint separable_program(GLenum stage, const char* source) {
  GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLuint program = glCreateProgram();
  glProgramParameteri(program, GL_PROGRAM_SEPARABLE, GL_TRUE);
  glAttachShader(program, shader);
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  return linked ? program : 0;
}
}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_pipeline", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  GLuint vertex = separable_program(GL_VERTEX_SHADER, kVertex);
  GLuint fragment = separable_program(GL_FRAGMENT_SHADER, kFragment);
  if (!vertex || !fragment) {
    fprintf(stderr, "probe_pipeline: separable programs do not link\n");
    return 2;
  }
  GLuint pipeline = 0;
  glGenProgramPipelines(1, &pipeline);
  glUseProgramStages(pipeline, GL_VERTEX_SHADER_BIT, vertex);
  glUseProgramStages(pipeline, GL_FRAGMENT_SHADER_BIT, fragment);
  glBindProgramPipeline(pipeline);
  glProgramUniform4f(fragment, glGetUniformLocation(fragment, "color"), 102 / 255.0f, 204 / 255.0f, 50 / 255.0f, 1);

  bind_fullscreen_quad(args.width, args.height);
  std::vector<uint8_t> image = draw_quad_frames(args.frames, args.width, args.height, w.display, w.surface);
  eglMakeCurrent(w.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(w.display, w.context);
  eglTerminate(w.display);
  return write_ppm(args.out, image, args.width, args.height) ? 0 : 3;
}
