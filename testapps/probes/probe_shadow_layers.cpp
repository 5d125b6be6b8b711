// Shadow maps the way engines lay them out: cascades in the layers of a depth 2D array, or a
// point light's six faces in a depth cube map. A depth-only pass draws a round occluder into
// each layer (or face) through one framebuffer re-attached layer by layer, then a full-screen
// pass samples every layer with a shadow sampler (hardware PCF) and shows them side by side:
// three columns of cascades, or a 3 x 2 grid of faces.
//   --layout array|cube     the shadow map (default array: 3 layers)
//   --storage mutable       glTexImage3D / glTexImage2D per face (default)
//             immutable     glTexStorage3D / glTexStorage2D(GL_TEXTURE_CUBE_MAP)
//             dsa           glCreateTextures, glTextureStorage*, glNamedFramebufferTextureLayer
//   --attach layered        the whole texture attached (glFramebufferTexture), cleared once and
//                           drawn by one draw whose geometry shader sends a copy of the
//                           occluder to each layer (gl_Layer), as one-pass shadow renderers do
//   --static 1              the shadow map drawn at the first frame only and sampled ever after
//                           (a cached shadow map of static geometry)
//   --moving 1              the occluders move from frame to frame (by 0.1 of a layer, back
//                           and forth): a layer's content from the frame before is stale
//   --each PREFIX           every frame's image also into PREFIX<frame>.ppm
//   --profile gles3         an OpenGL ES 3 context, its shaders in GLSL ES 3.00 (not with
//                           --storage dsa or --attach layered)
// The shadow map is 128 x 128 whatever the window's size. Exits 4 when glGetError reports an
// error at any frame, 5 when the shadow map does not answer as the app made it (its size, its
// layers, immutable format and levels).
//   pass "shadow": 128 x 128 x layers depth fragments at most; pass "lit": W x H
#define GL_GLEXT_PROTOTYPES 1
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "common/direct_gl.hpp"
#include "common/egl_setup.hpp"
#include "common/probe_main.hpp"

namespace {

constexpr int kShadowSize = 128;
constexpr int kCascades = 3;

const char* kOccluderVertex =
    "#version 330 core\nlayout(location=0) in vec2 pos;\nuniform vec2 offset;\nout vec2 p;\n"
    "void main(){ p = pos; gl_Position = vec4(pos * 0.45 + offset, 0.0, 1.0); }\n";
const char* kOccluderFragment =
    "#version 330 core\nin vec2 p;\nvoid main(){ if (dot(p, p) > 1.0) discard; /* shadow */ }\n";
// The layered pass: the occluder once per layer, moved by that layer's offset.
const char* kLayeredVertex =
    "#version 330 core\nlayout(location=0) in vec2 pos;\nout vec2 vp;\nvoid main(){ vp = pos; }\n";
const char* kLayeredGeometry =
    "#version 330 core\nlayout(triangles) in;\nlayout(triangle_strip, max_vertices = 18) out;\n"
    "uniform vec2 offsets[6];\nuniform int layers;\nin vec2 vp[];\nout vec2 p;\n"
    "void main(){ for (int l = 0; l < layers; ++l) { for (int i = 0; i < 3; ++i) {\n"
    "  gl_Layer = l; p = vp[i]; gl_Position = vec4(vp[i] * 0.45 + offsets[l], 0.0, 1.0); EmitVertex(); }\n"
    "  EndPrimitive(); } }\n";
const char* kLitVertex =
    "#version 330 core\nlayout(location=0) in vec2 pos;\nout vec2 uv;\n"
    "void main(){ uv = pos * 0.5 + 0.5; gl_Position = vec4(pos, 0.0, 1.0); }\n";
// The occluder sits at depth 0.5; 0.6 is behind it, in front of the cleared 1.0.
const char* kLitArray =
    "#version 330 core\nin vec2 uv;\nuniform sampler2DArrayShadow shadows;\nout vec4 frag;\n"
    "void main(){ float cell = uv.x * 3.0; float layer = min(floor(cell), 2.0);\n"
    "  float lit = texture(shadows, vec4(cell - layer, uv.y, layer, 0.6));\n"
    "  vec3 tint = vec3(0.3 + 0.3 * layer, 0.8, 1.0 - 0.3 * layer);\n"
    "  frag = vec4(tint * (0.25 + 0.75 * lit), 1.0); /* lit */ }\n";
const char* kLitCube =
    "#version 330 core\nin vec2 uv;\nuniform samplerCubeShadow shadows;\nout vec4 frag;\n"
    "void main(){ vec2 cell = uv * vec2(3.0, 2.0); vec2 at = min(floor(cell), vec2(2.0, 1.0));\n"
    "  int face = int(at.x) + 3 * int(at.y); vec2 st = (cell - at) * 2.0 - 1.0;\n"
    "  float s = st.x, t = st.y; vec3 d;\n"
    "  if (face == 0) d = vec3(1.0, -t, -s); else if (face == 1) d = vec3(-1.0, -t, s);\n"
    "  else if (face == 2) d = vec3(s, 1.0, t); else if (face == 3) d = vec3(s, -1.0, -t);\n"
    "  else if (face == 4) d = vec3(s, -t, 1.0); else d = vec3(-s, -t, -1.0);\n"
    "  float lit = texture(shadows, vec4(d, 0.6));\n"
    "  vec3 tint = vec3(0.2 + 0.15 * float(face), 0.8, 1.0 - 0.15 * float(face));\n"
    "  frag = vec4(tint * (0.25 + 0.75 * lit), 1.0); /* lit */ }\n";

bool g_es = false;  // --profile gles3

// A shader in GLSL ES 3.00 when the context is ES: its "#version 330 core" line replaced, and
// the precisions ES asks for (shadow samplers have no default one).
std::string in_dialect(const char* source) {
  std::string s = source;
  const std::string desktop = "#version 330 core\n";
  if (g_es && s.rfind(desktop, 0) == 0)
    s.replace(0, desktop.size(),
              "#version 300 es\nprecision highp float;\nprecision highp sampler2DArrayShadow;\n"
              "precision highp samplerCubeShadow;\n");
  return s;
}

GLuint program(const char* vs, const char* fs, const char* gs = nullptr) {
  const GLuint p = glCreateProgram();
  const GLuint v = compile_shader(GL_VERTEX_SHADER, in_dialect(vs).c_str()),
               f = compile_shader(GL_FRAGMENT_SHADER, in_dialect(fs).c_str());
  const GLuint g = gs ? compile_shader(GL_GEOMETRY_SHADER, gs) : 0;
  if (!v || !f || (gs && !g)) return 0;
  glAttachShader(p, v);
  glAttachShader(p, f);
  if (g) glAttachShader(p, g);
  glLinkProgram(p);
  GLint ok = 0;
  glGetProgramiv(p, GL_LINK_STATUS, &ok);
  return ok ? p : 0;
}

enum class Storage { kMutable, kImmutable, kDsa };

// The shadow map: depth, compared, filtered linearly (2 x 2 PCF).
GLuint shadow_map(bool cube, Storage storage) {
  const GLenum kind = cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D_ARRAY;
  GLuint t = 0;
  if (storage == Storage::kDsa) {
    glCreateTextures(kind, 1, &t);
    if (cube)
      glTextureStorage2D(t, 1, GL_DEPTH_COMPONENT32F, kShadowSize, kShadowSize);
    else
      glTextureStorage3D(t, 1, GL_DEPTH_COMPONENT32F, kShadowSize, kShadowSize, kCascades);
  } else {
    glGenTextures(1, &t);
    glBindTexture(kind, t);
    if (storage == Storage::kImmutable && cube) {
      glTexStorage2D(GL_TEXTURE_CUBE_MAP, 1, GL_DEPTH_COMPONENT32F, kShadowSize, kShadowSize);
    } else if (storage == Storage::kImmutable) {
      glTexStorage3D(GL_TEXTURE_2D_ARRAY, 1, GL_DEPTH_COMPONENT32F, kShadowSize, kShadowSize, kCascades);
    } else if (cube) {
      for (GLenum face = 0; face < 6; ++face)
        glTexImage2D(GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, 0, GL_DEPTH_COMPONENT32F, kShadowSize, kShadowSize, 0,
                     GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    } else {
      glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_DEPTH_COMPONENT32F, kShadowSize, kShadowSize, kCascades, 0,
                   GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
    }
  }
  glBindTexture(kind, t);
  glTexParameteri(kind, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(kind, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(kind, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(kind, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glTexParameteri(kind, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(kind, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  return t;
}

// The shadow map answers as the app made it, face by face, whatever the shim stores.
bool answers_as_made(GLuint t, bool cube, Storage storage) {
  const GLenum kind = cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D_ARRAY;
  glBindTexture(kind, t);
  bool ok = true;
  for (GLenum face = 0; face < (cube ? 6u : 1u); ++face) {
    const GLenum target = cube ? GL_TEXTURE_CUBE_MAP_POSITIVE_X + face : kind;
    GLint w = 0, h = 0, d = 0;
    glGetTexLevelParameteriv(target, 0, GL_TEXTURE_WIDTH, &w);
    glGetTexLevelParameteriv(target, 0, GL_TEXTURE_HEIGHT, &h);
    glGetTexLevelParameteriv(target, 0, GL_TEXTURE_DEPTH, &d);
    if (w != kShadowSize || h != kShadowSize || d != (cube ? 1 : kCascades)) {
      fprintf(stderr, "probe_shadow_layers: face/layer size %dx%dx%d\n", w, h, d);
      ok = false;
    }
  }
  if (storage == Storage::kDsa && !cube) {
    GLint w = 0, h = 0;
    glGetTextureLevelParameteriv(t, 0, GL_TEXTURE_WIDTH, &w);
    glGetTextureLevelParameteriv(t, 0, GL_TEXTURE_HEIGHT, &h);
    if (w != kShadowSize || h != kShadowSize) {
      fprintf(stderr, "probe_shadow_layers: by name %dx%d\n", w, h);
      ok = false;
    }
  }
  GLint immutable = GL_FALSE, levels = 0;
  glGetTexParameteriv(kind, GL_TEXTURE_IMMUTABLE_FORMAT, &immutable);
  glGetTexParameteriv(kind, GL_TEXTURE_IMMUTABLE_LEVELS, &levels);
  const bool made_immutable = storage != Storage::kMutable;
  if (immutable != (made_immutable ? GL_TRUE : GL_FALSE) || levels != (made_immutable ? 1 : 0)) {
    fprintf(stderr, "probe_shadow_layers: immutable %d, %d levels\n", immutable, levels);
    ok = false;
  }
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  bool cube = false, cached = false, moving = false, layered = false;
  Storage storage = Storage::kMutable;
  std::string each;
  for (int i = 1; i + 1 < argc; ++i) {
    if (!strcmp(argv[i], "--layout")) cube = !strcmp(argv[i + 1], "cube");
    if (!strcmp(argv[i], "--static")) cached = !strcmp(argv[i + 1], "1");
    if (!strcmp(argv[i], "--attach")) layered = !strcmp(argv[i + 1], "layered");
    if (!strcmp(argv[i], "--moving")) moving = !strcmp(argv[i + 1], "1");
    if (!strcmp(argv[i], "--each")) each = argv[i + 1];
    if (!strcmp(argv[i], "--profile")) g_es = !strcmp(argv[i + 1], "gles3");
    if (!strcmp(argv[i], "--storage"))
      storage = !strcmp(argv[i + 1], "immutable") ? Storage::kImmutable
                : !strcmp(argv[i + 1], "dsa")     ? Storage::kDsa
                                                  : Storage::kMutable;
  }
  const int w = args.width, h = args.height;
  EglFns egl;
  EglWindow win;
  if (g_es && (layered || storage == Storage::kDsa)) {
    fprintf(stderr, "probe_shadow_layers: --profile gles3 takes neither --attach layered nor --storage dsa\n");
    return 2;
  }
  if (!open_current_window("probe_shadow_layers", egl, g_es ? ContextKind::kGles3 : ContextKind::kCore45, w, h, &win))
    return 2;
  const GLuint occluder = layered ? program(kLayeredVertex, kOccluderFragment, kLayeredGeometry)
                                  : program(kOccluderVertex, kOccluderFragment),
               lit = program(kLitVertex, cube ? kLitCube : kLitArray);
  if (!occluder || !lit) {
    fprintf(stderr, "probe_shadow_layers: a program does not link\n");
    return 2;
  }
  bind_fullscreen_quad(w, h);
  const GLuint shadows = shadow_map(cube, storage);
  const int layers = cube ? 6 : kCascades;
  GLuint fbo = 0;
  if (storage == Storage::kDsa) {
    glCreateFramebuffers(1, &fbo);
    glNamedFramebufferDrawBuffer(fbo, GL_NONE);
    glNamedFramebufferReadBuffer(fbo, GL_NONE);
  } else {
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    const GLenum none = GL_NONE;
    glDrawBuffers(1, &none);
    glReadBuffer(GL_NONE);
  }
  // One layer (a cube map's face) attached at a time, as a shadow renderer walks its cascades.
  auto attach = [&](int layer) {
    if (layered && storage == Storage::kDsa)
      glNamedFramebufferTexture(fbo, GL_DEPTH_ATTACHMENT, shadows, 0);
    else if (layered)
      glFramebufferTexture(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, shadows, 0);
    else if (storage == Storage::kDsa)
      glNamedFramebufferTextureLayer(fbo, GL_DEPTH_ATTACHMENT, shadows, 0, layer);
    else if (cube)
      glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_CUBE_MAP_POSITIVE_X + layer, shadows, 0);
    else
      glFramebufferTextureLayer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, shadows, 0, layer);
  };
  glBindFramebuffer(GL_FRAMEBUFFER, fbo);
  attach(0);
  if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    fprintf(stderr, "probe_shadow_layers: framebuffer incomplete\n");
    return 2;
  }
  glUseProgram(lit);
  glUniform1i(glGetUniformLocation(lit, "shadows"), 0);
  const GLint offset = glGetUniformLocation(occluder, "offset"), offsets = glGetUniformLocation(occluder, "offsets");
  glProgramUniform1i(occluder, glGetUniformLocation(occluder, "layers"), layers);

  std::vector<uint8_t> image(static_cast<size_t>(w) * h * 4);
  GLenum error = glGetError();
  if (error != GL_NO_ERROR) fprintf(stderr, "probe_shadow_layers: GL error 0x%04x before the first frame\n", error);
  for (int f = 0; f < args.frames && error == GL_NO_ERROR; ++f) {
    if (f == 0 || !cached) {
      glBindFramebuffer(GL_FRAMEBUFFER, fbo);
      glViewport(0, 0, kShadowSize, kShadowSize);
      glEnable(GL_DEPTH_TEST);
      glUseProgram(occluder);
      const float shift = moving && f % 2 ? 0.2f : 0.0f;
      float at[12];
      for (int layer = 0; layer < layers; ++layer) {
        at[2 * layer] = 0.35f * ((layer % 3) - 1) + shift;
        at[2 * layer + 1] = 0.25f * ((layer % 2) ? 1.0f : -1.0f);
      }
      if (layered) {
        glClear(GL_DEPTH_BUFFER_BIT);  // every layer
        glUniform2fv(offsets, layers, at);
        glDrawArrays(GL_TRIANGLES, 0, 6);
      }
      for (int layer = 0; layer < layers && !layered; ++layer) {
        attach(layer);
        glClear(GL_DEPTH_BUFFER_BIT);
        glUniform2f(offset, at[2 * layer], at[2 * layer + 1]);
        glDrawArrays(GL_TRIANGLES, 0, 6);
      }
      glDisable(GL_DEPTH_TEST);
    }
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glViewport(0, 0, w, h);
    glUseProgram(lit);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(cube ? GL_TEXTURE_CUBE_MAP : GL_TEXTURE_2D_ARRAY, shadows);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, image.data());
    if (!each.empty()) write_ppm(each + std::to_string(f) + ".ppm", image, w, h);
    eglSwapBuffers(win.display, win.surface);
    error = glGetError();
    if (error != GL_NO_ERROR) fprintf(stderr, "probe_shadow_layers: GL error 0x%04x at frame %d\n", error, f);
  }
  const bool as_made = answers_as_made(shadows, cube, storage);
  if (error == GL_NO_ERROR) error = glGetError();
  const int rc = error != GL_NO_ERROR ? 4 : !as_made ? 5 : write_ppm(args.out, image, w, h) ? 0 : 3;
  eglMakeCurrent(win.display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
  eglDestroyContext(win.display, win.context);
  eglTerminate(win.display);
  return rc;
}
