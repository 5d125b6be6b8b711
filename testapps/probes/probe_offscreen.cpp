// Draws the way most games do: the known scene into a window-sized framebuffer (colour texture
// and depth renderbuffer), a quarter-sized copy of it (a bloom-like chain, never the window's
// size), then both composed into the window by a full-screen pass that samples them with
// normalised coordinates. The window is read back at the last frame.
//   --profile compat     a compatibility-profile context (as GLX apps and glmark2 get);
//   --profile gles3      an OpenGL ES 3 context, its shaders in GLSL ES 3.00
//   --format unsized     colour textures specified as GL_RGBA (GLES 2-era code), not GL_RGBA8
//   --format immutable   colour textures and a depth-stencil texture made by glTexStorage2D
//                        (GL 4.2+ engines), not glTexImage2D and a renderbuffer
//   --format dsa         the same made, attached and asked about by name (GL 4.5 direct state
//                        access: glCreateTextures, glTextureStorage2D, glNamedFramebufferTexture)
//   --format mipmapped   immutable too, the scene's colour a full mip chain (glTexStorage2D of
//                        every level) whose levels glGenerateMipmap fills each frame; the
//                        quarter pass reads its level 2 (bloom and auto-exposure chains)
//   --format multisample the scene drawn into a 4-sample framebuffer of multisample textures
//                        (colour by glTexImage2DMultisample, depth by glTexStorage2DMultisample)
//                        and resolved into the scene's texture by glBlitFramebuffer (MSAA)
//   --color FORMAT       with immutable textures, the colour textures' format: rgba8 (default),
//                        rg16 (16-bit normalised), rgba16f, r11f_g11f_b10f (HDR targets)
//   --read-fbo PATH      at the last frame also reads the scene's framebuffer back
//                        (glReadPixels of it, as screenshot and picking code does) into PATH,
//                        and prints the pixel under a "cursor" at the centre of the scene's
//                        small quad ("pick R G B A", one pixel read alone), and the same pixel
//                        copied by glCopyTexSubImage2D into a 1x1 texture and read from it
//                        ("copied R G B A")
//   --compose MODE       how the compose pass finds its texels: "uv" (default) interpolated
//                        coordinates; "fragcoord" gl_FragCoord divided by the window's size,
//                        set in a uniform (post-processing written for one resolution);
//                        "fetch" texelFetch at gl_FragCoord (the quarter at a quarter of it);
//                        "size" gl_FragCoord divided by textureSize (the quarter's times 4);
//                        "array" texelFetch at gl_FragCoord of a sampler array's elements;
//                        "parameter" texelFetch in a function taking the sampler
//   --twice 1            the compose pass drawn in two halves (scissored), the left one with the
//                        scene and quarter textures bound to each other's units: one program
//                        drawing other textures into the same framebuffer, draw after draw
//   --pipeline 1         the compose pass drawn by a program pipeline of separable programs
//                        (glCreateShaderProgramv), its uniforms set by glProgramUniform*
//   --viewport-indexed 1 every viewport set by glViewportIndexedf(0, ...) and the compose pass's
//                        scissor boxes (--twice) by glScissorIndexed, as Wine's wined3d does on
//                        drivers with viewport arrays; glGetFloati_v(GL_VIEWPORT, 0) must answer
//                        the box set (else exit 5)
//   --view 1             with immutable textures, the compose pass samples the scene through a
//                        glTextureView of its colour texture (format reinterpretation, sRGB
//                        views), made before the first frame
// Exits 4 when glGetError reports an error at any frame: none of the app's calls raises one;
// 5 when a texture does not answer as the app made it (size, immutable format and levels).
//   pass A, B: the known scene, into the window-sized framebuffer
//   pass "quarter": W/4 x H/4 fragments;  pass "compose": W x H fragments, into the window
#define GL_GLEXT_PROTOTYPES 1
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "common/direct_gl.hpp"
#include "common/egl_setup.hpp"
#include "common/probe_main.hpp"

namespace {

const char* kVertex =
    "#version 330 core\nlayout(location=0) in vec2 pos;\nout vec2 uv;\n"
    "void main(){ uv = pos * 0.5 + 0.5; gl_Position = vec4(pos, 0.0, 1.0); }\n";
const char* kQuarter =
    "#version 330 core\nin vec2 uv;\nuniform sampler2D scene;\nout vec4 frag;\n"
    "void main(){ frag = texture(scene, uv) * 0.5; /* quarter */ }\n";
const char* kCompose =
    "#version 330 core\nin vec2 uv;\nuniform sampler2D scene;\nuniform sampler2D quarter;\nout vec4 frag;\n"
    "void main(){ frag = texture(scene, uv) * 0.75 + texture(quarter, uv) * 0.5; /* compose */ }\n";

// The compose pass of each --compose mode: the same image, found three other ways.
const char* compose_source(const std::string& mode) {
  if (mode == "fragcoord")
    return "#version 330 core\nuniform sampler2D scene;\nuniform sampler2D quarter;\nuniform vec2 u_resolution;\n"
           "out vec4 frag;\nvoid main(){ vec2 uv = gl_FragCoord.xy / u_resolution;\n"
           "  frag = texture(scene, uv) * 0.75 + texture(quarter, uv) * 0.5; /* compose */ }\n";
  if (mode == "fetch")
    return "#version 330 core\nuniform sampler2D scene;\nuniform sampler2D quarter;\nout vec4 frag;\n"
           "void main(){ ivec2 p = ivec2(gl_FragCoord.xy);\n"
           "  frag = texelFetch(scene, p, 0) * 0.75 + texelFetch(quarter, p / 4, 0) * 0.5; /* compose */ }\n";
  if (mode == "size")
    return "#version 330 core\nuniform sampler2D scene;\nuniform sampler2D quarter;\nout vec4 frag;\n"
           "void main(){ vec2 uv = gl_FragCoord.xy / vec2(textureSize(scene, 0));\n"
           "  vec2 quv = gl_FragCoord.xy / vec2(textureSize(quarter, 0) * 4);\n"
           "  frag = texture(scene, uv) * 0.75 + texture(quarter, quv) * 0.5; /* compose */ }\n";
  if (mode == "array")
    return "#version 330 core\nuniform sampler2D images[2];\nout vec4 frag;\n"
           "void main(){ ivec2 p = ivec2(gl_FragCoord.xy);\n"
           "  frag = texelFetch(images[0], p, 0) * 0.75 + texelFetch(images[1], p / 4, 0) * 0.5; /* compose */ }\n";
  if (mode == "parameter")
    return "#version 330 core\nuniform sampler2D scene;\nuniform sampler2D quarter;\nout vec4 frag;\n"
           "vec4 at(sampler2D s, ivec2 p) { return texelFetch(s, p, 0); }\n"
           "void main(){ ivec2 p = ivec2(gl_FragCoord.xy);\n"
           "  frag = at(scene, p) * 0.75 + at(quarter, p / 4) * 0.5; /* compose */ }\n";
  return kCompose;
}

// The compose pass as a program pipeline: a separable vertex program and `fs`.
GLuint compose_pipeline(const char* fs, GLuint* fragment_program) {
  const char* vs =
      "#version 450 core\nlayout(location=0) in vec2 pos;\nout gl_PerVertex { vec4 gl_Position; };\n"
      "void main(){ gl_Position = vec4(pos, 0.0, 1.0); }\n";
  const GLuint vertex = glCreateShaderProgramv(GL_VERTEX_SHADER, 1, &vs);
  *fragment_program = glCreateShaderProgramv(GL_FRAGMENT_SHADER, 1, &fs);
  GLint ok_v = 0, ok_f = 0;
  glGetProgramiv(vertex, GL_LINK_STATUS, &ok_v);
  glGetProgramiv(*fragment_program, GL_LINK_STATUS, &ok_f);
  if (!ok_v || !ok_f) return 0;
  GLuint pipeline = 0;
  glGenProgramPipelines(1, &pipeline);
  glUseProgramStages(pipeline, GL_VERTEX_SHADER_BIT, vertex);
  glUseProgramStages(pipeline, GL_FRAGMENT_SHADER_BIT, *fragment_program);
  return pipeline;
}

// A shader in GLSL ES 3.00 when `es`: its "#version 330 core" line replaced.
std::string in_dialect(const char* source, bool es) {
  std::string s = source;
  const std::string desktop = "#version 330 core\n";
  if (es && s.rfind(desktop, 0) == 0) s.replace(0, desktop.size(), "#version 300 es\nprecision highp float;\n");
  return s;
}

GLuint program(const char* vs, const char* fs, bool es = false) {
  GLuint p = glCreateProgram();
  for (auto [stage, text] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
    const std::string src = in_dialect(text, es);
    const GLuint s = compile_shader(stage, src.c_str());
    if (!s) return 0;
    glAttachShader(p, s);
  }
  glLinkProgram(p);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  return ok ? p : 0;
}

enum class Format { kSized, kUnsized, kImmutable, kDsa, kMipmapped, kMultisample };
constexpr int kSamples = 4;

// A multisample texture answers as the app made it: its size, samples, and immutability.
bool multisample_answers_as_made(GLuint texture, int w, int h, bool immutable) {
  glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, texture);
  GLint width = 0, height = 0, samples = 0, format = GL_FALSE;
  glGetTexLevelParameteriv(GL_TEXTURE_2D_MULTISAMPLE, 0, GL_TEXTURE_WIDTH, &width);
  glGetTexLevelParameteriv(GL_TEXTURE_2D_MULTISAMPLE, 0, GL_TEXTURE_HEIGHT, &height);
  glGetTexLevelParameteriv(GL_TEXTURE_2D_MULTISAMPLE, 0, GL_TEXTURE_SAMPLES, &samples);
  glGetTexParameteriv(GL_TEXTURE_2D_MULTISAMPLE, GL_TEXTURE_IMMUTABLE_FORMAT, &format);
  const bool ok = width == w && height == h && samples == kSamples && format == (immutable ? GL_TRUE : GL_FALSE);
  if (!ok)
    fprintf(stderr, "probe_offscreen: multisample texture %u answers %dx%d, %d samples, immutable %d\n", texture, width,
            height, samples, format);
  return ok;
}

GLuint storage_texture(int w, int h, GLenum internal_format, Format format, int levels = 1) {
  GLuint t = 0;
  if (format == Format::kDsa) {
    glCreateTextures(GL_TEXTURE_2D, 1, &t);
    glTextureStorage2D(t, levels, internal_format, w, h);
  } else {
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexStorage2D(GL_TEXTURE_2D, levels, internal_format, w, h);
  }
  return t;
}

int full_chain(int w, int h) {
  int levels = 1;
  while ((std::max(w, h) >> levels) > 0) ++levels;
  return levels;
}

GLenum g_color_format = GL_RGBA8;  // of immutable colour textures (--color)

GLuint color_texture(int w, int h, Format format, int levels = 1) {
  GLuint t = 0;
  if (format == Format::kImmutable || format == Format::kDsa || format == Format::kMipmapped) {
    t = storage_texture(w, h, g_color_format, format, levels);  // bound, unless by name
  } else {
    glGenTextures(1, &t);
    glBindTexture(GL_TEXTURE_2D, t);
    glTexImage2D(GL_TEXTURE_2D, 0, format == Format::kUnsized ? GL_RGBA : GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 nullptr);
  }
  for (auto [pname, value] :
       {std::pair{GL_TEXTURE_MIN_FILTER, GL_LINEAR}, std::pair{GL_TEXTURE_MAG_FILTER, GL_LINEAR},
        std::pair{GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE}, std::pair{GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE}}) {
    if (format == Format::kDsa)
      glTextureParameteri(t, pname, value);
    else
      glTexParameteri(GL_TEXTURE_2D, pname, value);
  }
  return t;
}

// The texture answers as the app made it, whatever the shim stores.
bool answers_as_made(GLuint texture, int w, int h, bool immutable, bool by_name, int made_levels = 1) {
  GLint width = 0, height = 0, format = GL_FALSE, levels = 0;
  if (by_name) {
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_WIDTH, &width);
    glGetTextureLevelParameteriv(texture, 0, GL_TEXTURE_HEIGHT, &height);
    glGetTextureParameteriv(texture, GL_TEXTURE_IMMUTABLE_FORMAT, &format);
    glGetTextureParameteriv(texture, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
  } else {
    glBindTexture(GL_TEXTURE_2D, texture);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_WIDTH, &width);
    glGetTexLevelParameteriv(GL_TEXTURE_2D, 0, GL_TEXTURE_HEIGHT, &height);
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_IMMUTABLE_FORMAT, &format);
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
  }
  bool ok = width == w && height == h && format == (immutable ? GL_TRUE : GL_FALSE) &&
            levels == (immutable ? made_levels : 0);
  if (made_levels > 1 && !by_name) {  // every level's size, and the maximum level the app set
    for (int l = 1; l < made_levels; ++l) {
      glGetTexLevelParameteriv(GL_TEXTURE_2D, l, GL_TEXTURE_WIDTH, &width);
      glGetTexLevelParameteriv(GL_TEXTURE_2D, l, GL_TEXTURE_HEIGHT, &height);
      ok = ok && width == std::max(1, w >> l) && height == std::max(1, h >> l);
    }
    GLint max_level = 0;
    glGetTexParameteriv(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, &max_level);
    ok = ok && max_level == 1000;
  }
  if (!ok)
    fprintf(stderr, "probe_offscreen: texture %u answers %dx%d, immutable %d, %d levels\n", texture, width, height,
            format, levels);
  return ok;
}

// The scene's framebuffer read back whole, a pixel of it alone, and the same pixel copied into
// a texture; the framebuffer bindings are left as they were.
void read_scene_framebuffer(GLuint fbo, int w, int h, const std::string& path) {
  GLint read = 0;
  glGetIntegerv(GL_READ_FRAMEBUFFER_BINDING, &read);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
  glReadBuffer(GL_COLOR_ATTACHMENT0);
  std::vector<uint8_t> whole(static_cast<size_t>(w) * h * 4);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, whole.data());
  write_ppm(path, whole, w, h);
  const int cx = w * 5 / 8, cy = h * 5 / 8;  // the small quad's centre
  uint8_t pick[4] = {};
  glReadPixels(cx, cy, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, pick);
  printf("pick %d %d %d %d\n", pick[0], pick[1], pick[2], pick[3]);
  GLuint texture = 0, copy_fbo = 0;
  GLint bound = 0, draw = 0;
  glGetIntegerv(GL_TEXTURE_BINDING_2D, &bound);
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &draw);
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  glCopyTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, cx, cy, 1, 1);
  glGenFramebuffers(1, &copy_fbo);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, copy_fbo);
  glFramebufferTexture2D(GL_READ_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, texture, 0);
  uint8_t copied[4] = {};
  glReadPixels(0, 0, 1, 1, GL_RGBA, GL_UNSIGNED_BYTE, copied);
  printf("copied %d %d %d %d\n", copied[0], copied[1], copied[2], copied[3]);
  glBindFramebuffer(GL_READ_FRAMEBUFFER, static_cast<GLuint>(read));
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(draw));
  glDeleteFramebuffers(1, &copy_fbo);
  glBindTexture(GL_TEXTURE_2D, static_cast<GLuint>(bound));
  glDeleteTextures(1, &texture);
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  bool compat = false, es = false;
  Format format = Format::kSized;
  std::string read_fbo_path, compose = "uv";
  bool pipeline = false, twice = false, view = false, indexed = false;
  for (int i = 1; i + 1 < argc; ++i) {
    if (!strcmp(argv[i], "--pipeline")) pipeline = !strcmp(argv[i + 1], "1");
    if (!strcmp(argv[i], "--twice")) twice = !strcmp(argv[i + 1], "1");
    if (!strcmp(argv[i], "--view")) view = !strcmp(argv[i + 1], "1");
    if (!strcmp(argv[i], "--viewport-indexed")) indexed = !strcmp(argv[i + 1], "1");
    if (!strcmp(argv[i], "--compose")) compose = argv[i + 1];
    if (!strcmp(argv[i], "--read-fbo")) read_fbo_path = argv[i + 1];
    if (!strcmp(argv[i], "--color"))
      g_color_format = !strcmp(argv[i + 1], "rg16")             ? GL_RG16
                       : !strcmp(argv[i + 1], "rgba16f")        ? GL_RGBA16F
                       : !strcmp(argv[i + 1], "r11f_g11f_b10f") ? GL_R11F_G11F_B10F
                                                                : GL_RGBA8;
    if (!strcmp(argv[i], "--profile")) {
      compat = !strcmp(argv[i + 1], "compat");
      es = !strcmp(argv[i + 1], "gles3");
    }
    if (!strcmp(argv[i], "--format"))
      format = !strcmp(argv[i + 1], "unsized")       ? Format::kUnsized
               : !strcmp(argv[i + 1], "immutable")   ? Format::kImmutable
               : !strcmp(argv[i + 1], "dsa")         ? Format::kDsa
               : !strcmp(argv[i + 1], "mipmapped")   ? Format::kMipmapped
               : !strcmp(argv[i + 1], "multisample") ? Format::kMultisample
                                                     : Format::kSized;
  }
  const bool dsa = format == Format::kDsa, mipmapped = format == Format::kMipmapped;
  const bool immutable = format == Format::kImmutable || dsa || mipmapped;
  const int w = args.width, h = args.height;
  EglFns egl;
  EglWindow win;
  if (!open_current_window("probe_offscreen", egl,
                           es       ? ContextKind::kGles3
                           : compat ? ContextKind::kCompat
                                    : ContextKind::kCore45,
                           w, h, &win))
    return 2;
  GlFns gl;
#define DIRECT(type, name) gl.name = &::gl##name;
  PROBE_GL_FUNCTIONS(DIRECT)
#undef DIRECT
  KnownScene scene(gl, es ? ShaderDialect::kEssl300 : ShaderDialect::kGlsl330Core, w, h);
  const GLuint quarter_program = program(kVertex, kQuarter, es),
               compose_program = program(kVertex, compose_source(compose), es);
  if (!scene.ok() || !quarter_program || !compose_program) {
    fprintf(stderr, "probe_offscreen: %s\n", scene.ok() ? "a program does not link" : scene.error().c_str());
    return 2;
  }
  GLint scene_vao = 0;  // the known scene's vertex array, bound by it
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &scene_vao);
  bind_fullscreen_quad(w, h);
  GLint full_vao = 0;
  glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &full_vao);

  const int scene_levels = mipmapped ? full_chain(w, h) : 1;
  const GLuint scene_color = color_texture(w, h, format, scene_levels),
               quarter_color = color_texture(w / 4, h / 4, format);
  if (mipmapped) {
    glBindTexture(GL_TEXTURE_2D, scene_color);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  }
  GLuint depth = 0, fbo[2] = {0, 0};
  if (immutable) {
    depth = storage_texture(w, h, GL_DEPTH24_STENCIL8, format);
  } else {
    glGenRenderbuffers(1, &depth);
    glBindRenderbuffer(GL_RENDERBUFFER, depth);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
  }
  if (dsa) {
    glCreateFramebuffers(2, fbo);
    glNamedFramebufferTexture(fbo[0], GL_COLOR_ATTACHMENT0, scene_color, 0);
    glNamedFramebufferTexture(fbo[0], GL_DEPTH_STENCIL_ATTACHMENT, depth, 0);
    glNamedFramebufferTexture(fbo[1], GL_COLOR_ATTACHMENT0, quarter_color, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo[1]);
  } else {
    glGenFramebuffers(2, fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo[0]);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, scene_color, 0);
    if (immutable)
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_TEXTURE_2D, depth, 0);
    else
      glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, depth);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo[1]);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, quarter_color, 0);
  }
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    fprintf(stderr, "probe_offscreen: framebuffer incomplete\n");
    return 2;
  }
  // MSAA: the scene's own framebuffer, resolved into fbo[0] after the scene's draws.
  const bool multisample = format == Format::kMultisample;
  GLuint ms_fbo = 0, ms_color = 0, ms_depth = 0;
  if (multisample) {
    glGenTextures(1, &ms_color);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_color);
    glTexImage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, kSamples, GL_RGBA8, w, h, GL_TRUE);
    glGenTextures(1, &ms_depth);
    glBindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_depth);
    glTexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, kSamples, GL_DEPTH24_STENCIL8, w, h, GL_TRUE);
    glGenFramebuffers(1, &ms_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, ms_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE, ms_color, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_TEXTURE_2D_MULTISAMPLE, ms_depth, 0);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      fprintf(stderr, "probe_offscreen: multisample framebuffer incomplete\n");
      return 2;
    }
  }
  // What the compose pass samples the scene through: its texture, or a view of it.
  GLuint scene_sampled = scene_color;
  if (view && immutable) {
    glGenTextures(1, &scene_sampled);
    glTextureView(scene_sampled, GL_TEXTURE_2D, scene_color, g_color_format, 0, static_cast<GLuint>(scene_levels), 0,
                  1);
    if (mipmapped) {
      glBindTexture(GL_TEXTURE_2D, scene_sampled);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    }
  }
  GLuint compose_stages = 0, compose_fragment = compose_program;
  if (pipeline && !(compose_stages = compose_pipeline(compose_source(compose), &compose_fragment))) {
    fprintf(stderr, "probe_offscreen: the compose pipeline's programs do not link\n");
    return 2;
  }
  glProgramUniform1i(compose_fragment, glGetUniformLocation(compose_fragment, "scene"), 0);
  glProgramUniform1i(compose_fragment, glGetUniformLocation(compose_fragment, "quarter"), 1);
  const GLint images[2] = {0, 1};
  glProgramUniform1iv(compose_fragment, glGetUniformLocation(compose_fragment, "images"), 2, images);
  glProgramUniform2f(compose_fragment, glGetUniformLocation(compose_fragment, "u_resolution"), static_cast<float>(w),
                     static_cast<float>(h));

  bool boxes_answered = true;  // glGetFloati_v(GL_VIEWPORT, 0) answered each box set by index
  auto set_viewport = [&](int vw, int vh) {
    if (!indexed) return glViewport(0, 0, vw, vh);
    glViewportIndexedf(0, 0, 0, static_cast<GLfloat>(vw), static_cast<GLfloat>(vh));
    GLfloat box[4] = {};
    glGetFloati_v(GL_VIEWPORT, 0, box);
    boxes_answered = boxes_answered && box[0] == 0 && box[1] == 0 && box[2] == vw && box[3] == vh;
  };
  auto set_scissor = [&](int x, int sw) {
    if (indexed)
      glScissorIndexed(0, x, 0, sw, h);
    else
      glScissor(x, 0, sw, h);
  };
  std::vector<uint8_t> image;
  GLenum error = glGetError();
  if (error != GL_NO_ERROR) fprintf(stderr, "probe_offscreen: GL error 0x%04x before the first frame\n", error);
  for (int f = 0; f < args.frames && error == GL_NO_ERROR; ++f) {
    glBindFramebuffer(GL_FRAMEBUFFER, multisample ? ms_fbo : fbo[0]);
    set_viewport(w, h);
    glBindVertexArray(static_cast<GLuint>(scene_vao));
    scene.draw_frame(f);
    if (multisample) {  // resolved
      glBindFramebuffer(GL_READ_FRAMEBUFFER, ms_fbo);
      glBindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo[0]);
      glBlitFramebuffer(0, 0, w, h, 0, 0, w, h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }

    glBindFramebuffer(GL_FRAMEBUFFER, fbo[1]);
    set_viewport(w / 4, h / 4);
    glBindVertexArray(static_cast<GLuint>(full_vao));
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, scene_color);
    if (mipmapped) glGenerateMipmap(GL_TEXTURE_2D);  // the quarter pass's minification reads level 2
    glUseProgram(quarter_program);
    glDrawArrays(GL_TRIANGLES, 0, 6);

    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    set_viewport(w, h);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, scene_sampled);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, quarter_color);
    if (compose_stages) {
      glUseProgram(0);
      glBindProgramPipeline(compose_stages);
    } else {
      glUseProgram(compose_program);
    }
    if (twice) {
      glEnable(GL_SCISSOR_TEST);
      set_scissor(0, w / 2);
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, quarter_color);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, scene_color);
      glDrawArrays(GL_TRIANGLES, 0, 6);
      set_scissor(w / 2, w - w / 2);
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, scene_sampled);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, quarter_color);
    }
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glDisable(GL_SCISSOR_TEST);
    glBindProgramPipeline(0);
    if (f + 1 == args.frames) image = scene.read_rgba();
    if (f + 1 == args.frames && !read_fbo_path.empty()) read_scene_framebuffer(fbo[0], w, h, read_fbo_path);
    eglSwapBuffers(win.display, win.surface);
    error = glGetError();
    if (error != GL_NO_ERROR) fprintf(stderr, "probe_offscreen: GL error 0x%04x at frame %d\n", error, f);
  }
  // After the frames (a scaled texture is stored at its scale by now).
  const bool as_made = answers_as_made(scene_color, w, h, immutable, dsa, scene_levels) &&
                       answers_as_made(quarter_color, w / 4, h / 4, immutable, dsa) &&
                       (!immutable || answers_as_made(depth, w, h, true, dsa)) &&
                       (!multisample || (multisample_answers_as_made(ms_color, w, h, false) &&
                                         multisample_answers_as_made(ms_depth, w, h, true)));
  if (error == GL_NO_ERROR) error = glGetError();
  if (!boxes_answered) fprintf(stderr, "probe_offscreen: glGetFloati_v(GL_VIEWPORT, 0) did not answer the box set\n");
  const int rc = error != GL_NO_ERROR ? 4 : !as_made || !boxes_answered ? 5 : write_ppm(args.out, image, w, h) ? 0 : 3;
  eglMakeCurrent(win.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(win.display, win.context);
  eglTerminate(win.display);
  return rc;
}
