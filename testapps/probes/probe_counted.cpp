// A shader with hand-countable work for instrumentation tests: a full-window quad whose
// fragment shader loops over a uniform number of texture taps and takes a branch in the
// left 8 columns only. It also checks what an app can see of its shader: glGetShaderSource
// and GL_SHADER_SOURCE_LENGTH must return its own source (exit code 4 if not), and prints
// its program's interface (uniforms, attributes, uniform blocks) for tests to compare, and on
// stderr whether glGetProgramBinary gave it a binary to cache. With --contexts 2, the program
// is built in one context and drawn in a second one that shares its objects.
//
// Hand counts (instrument/instrument.hpp's rule), with taps = 3 on a W x H window:
//   vertex:   gl_Position = vec4(pos, 0.0, 1.0)            2 instructions, 0 texel accesses
//   fragment: sum = vec4(0.0); i = 0                        2
//             i < taps, evaluated taps + 1 times            4
//             sum += texture(tex, vec2(float(i) * 0.25, 0.5)), taps times:
//               +=, texture, vec2(), float(), *            15 (and 3 texel accesses)
//             ++i, taps times                               3
//             gl_FragCoord.x < 8.0                          1
//             sum *= 0.5 (8 of W columns)                   1 * 8 / W
//             frag = sum / float(taps): =, /, float()       3
//   → 28 + 8 / W instructions and 3 texel accesses per fragment.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "common/egl_setup.hpp"
#include "common/direct_gl.hpp"
#include "common/known_scene.hpp"

namespace {
const char* const kVertex =
    "#version 330 core\n"
    "layout(location=0) in vec2 pos;\n"
    "void main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n";
const char* const kFragment =
    "#version 330 core\n"
    "uniform sampler2D tex;\n"
    "uniform int taps;\n"
    "out vec4 frag;\n"
    "void main() {\n"
    "  vec4 sum = vec4(0.0);\n"
    "  for (int i = 0; i < taps; ++i)\n"
    "    sum += texture(tex, vec2(float(i) * 0.25, 0.5));\n"
    "  if (gl_FragCoord.x < 8.0) sum *= 0.5;\n"
    "  frag = sum / float(taps);\n"
    "}\n";

// The app's view of its shader is unchanged.
bool source_round_trips(GLuint shader, const char* source) {
  GLint length = 0;
  glGetShaderiv(shader, GL_SHADER_SOURCE_LENGTH, &length);
  std::vector<char> back(std::strlen(source) + 16, 'x');
  GLsizei written = 0;
  glGetShaderSource(shader, static_cast<GLsizei>(back.size()), &written, back.data());
  return length == GLint(std::strlen(source) + 1) && written == GLsizei(std::strlen(source)) &&
         std::strcmp(back.data(), source) == 0;
}

// Every active resource of `interface` with its name and location (or binding), one a line.
void print_interface(GLuint program, GLenum interface, GLenum location_property) {
  GLint count = 0;
  glGetProgramInterfaceiv(program, interface, GL_ACTIVE_RESOURCES, &count);
  for (GLint i = 0; i < count; ++i) {
    char name[256] = {};
    glGetProgramResourceName(program, interface, static_cast<GLuint>(i), sizeof name, nullptr, name);
    GLint location = -1;
    glGetProgramResourceiv(program, interface, static_cast<GLuint>(i), 1, &location_property, 1, nullptr, &location);
    printf("interface %#x: %s at %d\n", interface, name, location);
  }
}

GLuint compile(GLenum stage, const char* source, bool* same_source) {
  GLuint s = compile_shader(stage, source);
  if (s) *same_source = *same_source && source_round_trips(s, source);
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  bool shared = false;  // options come in pairs, as in parse_probe_args
  for (int i = 1; i + 1 < argc; i += 2)
    shared = shared || (std::strcmp(argv[i], "--contexts") == 0 && std::atoi(argv[i + 1]) == 2);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_counted", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  bool same_source = true;
  GLuint vs = compile(GL_VERTEX_SHADER, kVertex, &same_source);
  GLuint fs = compile(GL_FRAGMENT_SHADER, kFragment, &same_source);
  GLuint program = glCreateProgram();
  glAttachShader(program, vs);
  glAttachShader(program, fs);
  glLinkProgram(program);
  GLint linked = 0;
  glGetProgramiv(program, GL_LINK_STATUS, &linked);
  if (!vs || !fs || !linked) {
    fprintf(stderr, "probe_counted: shaders do not build\n");
    return 2;
  }
  if (!same_source) {
    fprintf(stderr, "probe_counted: glGetShaderSource does not return the app's source\n");
    return 4;
  }
  GLint binary_size = 0;
  glGetProgramiv(program, GL_PROGRAM_BINARY_LENGTH, &binary_size);
  std::vector<char> binary(static_cast<size_t>(binary_size > 0 ? binary_size : 1));
  GLsizei binary_length = 0;
  GLenum binary_format = 0;
  glGetProgramBinary(program, static_cast<GLsizei>(binary.size()), &binary_length, &binary_format, binary.data());
  fprintf(stderr, "probe_counted: program binary %s\n", binary_length > 0 ? "given" : "empty");
  print_interface(program, GL_UNIFORM, GL_LOCATION);
  print_interface(program, GL_PROGRAM_INPUT, GL_LOCATION);
  print_interface(program, GL_PROGRAM_OUTPUT, GL_LOCATION);
  print_interface(program, GL_UNIFORM_BLOCK, GL_BUFFER_BINDING);
  EglWindow drawing = w;
  if (shared) {
    std::string error;
    if (!egl_create(egl, ContextKind::kCore45, args.width, args.height, w.context, &drawing, &error, w.display)) {
      fprintf(stderr, "probe_counted: %s\n", error.c_str());
      return 2;
    }
    eglMakeCurrent(drawing.display, drawing.surface, drawing.surface, drawing.context);
  }
  // A 4x4 texture of distinct texels.
  std::vector<unsigned char> texels(4 * 4 * 4);
  for (size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<unsigned char>(i * 13 + 7);
  GLuint tex = 0;
  glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 4, 4, 0, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  bind_fullscreen_quad(args.width, args.height);
  glUseProgram(program);
  glUniform1i(glGetUniformLocation(program, "tex"), 0);
  glUniform1i(glGetUniformLocation(program, "taps"), 3);

  std::vector<uint8_t> image = draw_quad_frames(args.frames, args.width, args.height, drawing.display, drawing.surface);
  eglMakeCurrent(w.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  if (shared) eglDestroyContext(w.display, drawing.context);
  eglDestroyContext(w.display, w.context);
  eglTerminate(w.display);
  if (!write_ppm(args.out, image, args.width, args.height)) return 3;
  return 0;
}
