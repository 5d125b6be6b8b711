// A GLX window under X (run it under Xvfb): glXCreateContextAttribsARB and every GL function
// from glXGetProcAddressARB, as GLFW and SDL do on X11.
//   --samples N   a multisampled window (as SDL_GL_MULTISAMPLESAMPLES asks); exits 5 when
//                 GL_SAMPLES of the default framebuffer does not answer N at the end (or
//                 GL_DOUBLEBUFFER, always asked, not 1: Warzone 2100 refuses to run then)
//   --slanted 1   after the known scene, a slanted triangle whose edges antialiasing shows
//   --blit-through 1  after each frame's drawing, the window is blitted into a window-sized
//                 framebuffer of the app's, the window cleared, and the copy blitted back
//                 (as a post-process that starts from a copy of the back buffer)
//   --swapped-out PATH  after the last swap, the back buffer as a PPM: what was swapped, where
//                 the driver keeps it (llvmpipe's GLX does; the spec leaves it undefined)
#include <GL/glx.h>
#include <X11/Xlib.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <utility>
#include <vector>

#include "common/probe_main.hpp"

namespace {

// A triangle across the window at a slant, in its own program (its own pass).
struct SlantedTriangle {
  unsigned program = 0, vao = 0, vbo = 0;
  bool make(const GlFns& gl) {
    const char* vs =
        "#version 330 core\nlayout(location=0) in vec2 pos;\nvoid main(){ gl_Position = vec4(pos, 0, 1); }\n";
    const char* fs =
        "#version 330 core\nout vec4 frag;\nvoid main(){ frag = vec4(0.95, 0.9, 0.2, 1.0); /* slanted */ }\n";
    program = gl.CreateProgram();
    for (auto [stage, src] : {std::pair{GL_VERTEX_SHADER, vs}, std::pair{GL_FRAGMENT_SHADER, fs}}) {
      const unsigned s = gl.CreateShader(stage);
      gl.ShaderSource(s, 1, &src, nullptr);
      gl.CompileShader(s);
      gl.AttachShader(program, s);
    }
    gl.LinkProgram(program);
    int linked = 0;
    gl.GetProgramiv(program, GL_LINK_STATUS, &linked);
    static const float kVertices[] = {-0.9f, -0.8f, 0.9f, 0.6f, 0.2f, 0.95f};
    GLint scene_vao = 0, scene_buffer = 0;
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &scene_vao);
    glGetIntegerv(GL_ARRAY_BUFFER_BINDING, &scene_buffer);
    gl.GenVertexArrays(1, &vao);
    gl.BindVertexArray(vao);
    gl.GenBuffers(1, &vbo);
    gl.BindBuffer(GL_ARRAY_BUFFER, vbo);
    gl.BufferData(GL_ARRAY_BUFFER, sizeof kVertices, kVertices, GL_STATIC_DRAW);
    gl.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
    gl.EnableVertexAttribArray(0);
    gl.BindVertexArray(static_cast<unsigned>(scene_vao));
    gl.BindBuffer(GL_ARRAY_BUFFER, static_cast<unsigned>(scene_buffer));
    return linked != 0;
  }
  void draw(const GlFns& gl) const {
    GLint scene_vao = 0, scene_program = 0;
    glGetIntegerv(GL_VERTEX_ARRAY_BINDING, &scene_vao);
    glGetIntegerv(GL_CURRENT_PROGRAM, &scene_program);
    gl.UseProgram(program);
    gl.BindVertexArray(vao);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.BindVertexArray(static_cast<unsigned>(scene_vao));
    gl.UseProgram(static_cast<unsigned>(scene_program));
  }
};

// The window into a framebuffer of the app's and back, at the same size (as a multisampled
// window takes blits).
struct BlitThrough {
  PFNGLGENFRAMEBUFFERSPROC GenFramebuffers = nullptr;
  PFNGLBINDFRAMEBUFFERPROC BindFramebuffer = nullptr;
  PFNGLGENRENDERBUFFERSPROC GenRenderbuffers = nullptr;
  PFNGLBINDRENDERBUFFERPROC BindRenderbuffer = nullptr;
  PFNGLRENDERBUFFERSTORAGEPROC RenderbufferStorage = nullptr;
  PFNGLFRAMEBUFFERRENDERBUFFERPROC FramebufferRenderbuffer = nullptr;
  PFNGLBLITFRAMEBUFFERPROC BlitFramebuffer = nullptr;
  unsigned fbo = 0, color = 0;
  int width = 0, height = 0;
  template <typename F>
  static void load(F& f, const char* name) {
    f = reinterpret_cast<F>(glXGetProcAddressARB(reinterpret_cast<const GLubyte*>(name)));
  }
  bool make(int w, int h) {
    load(GenFramebuffers, "glGenFramebuffers");
    load(BindFramebuffer, "glBindFramebuffer");
    load(GenRenderbuffers, "glGenRenderbuffers");
    load(BindRenderbuffer, "glBindRenderbuffer");
    load(RenderbufferStorage, "glRenderbufferStorage");
    load(FramebufferRenderbuffer, "glFramebufferRenderbuffer");
    load(BlitFramebuffer, "glBlitFramebuffer");
    if (!GenFramebuffers || !BindFramebuffer || !GenRenderbuffers || !BindRenderbuffer || !RenderbufferStorage ||
        !FramebufferRenderbuffer || !BlitFramebuffer)
      return false;
    width = w;
    height = h;
    GenRenderbuffers(1, &color);
    BindRenderbuffer(GL_RENDERBUFFER, color);
    RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    GenFramebuffers(1, &fbo);
    BindFramebuffer(GL_FRAMEBUFFER, fbo);
    FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color);
    BindFramebuffer(GL_FRAMEBUFFER, 0);
    return true;
  }
  void run() const {
    BindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    BindFramebuffer(GL_DRAW_FRAMEBUFFER, fbo);
    BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    BindFramebuffer(GL_FRAMEBUFFER, 0);
    glClearColor(1.0f, 0.0f, 1.0f, 1.0f);  // what shows if the copy does not come back
    glClear(GL_COLOR_BUFFER_BIT);
    BindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
    BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    BlitFramebuffer(0, 0, width, height, 0, 0, width, height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    BindFramebuffer(GL_FRAMEBUFFER, 0);
  }
};

}  // namespace

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  Display* dpy = XOpenDisplay(nullptr);
  if (!dpy) {
    fprintf(stderr, "probe_glx: cannot open X display\n");
    return 2;
  }
  int samples = 0;
  bool want_blit = false;
  bool want_slanted = false;
  const char* swapped_out = nullptr;
  for (int i = 1; i + 1 < argc; ++i) {
    if (!strcmp(argv[i], "--samples")) samples = atoi(argv[i + 1]);
    if (!strcmp(argv[i], "--slanted")) want_slanted = atoi(argv[i + 1]) != 0;
    if (!strcmp(argv[i], "--blit-through")) want_blit = atoi(argv[i + 1]) != 0;
    if (!strcmp(argv[i], "--swapped-out")) swapped_out = argv[i + 1];
  }
  std::vector<int> fb_attribs = {GLX_X_RENDERABLE,  True,
                                 GLX_DRAWABLE_TYPE, GLX_WINDOW_BIT,
                                 GLX_RENDER_TYPE,   GLX_RGBA_BIT,
                                 GLX_RED_SIZE,      8,
                                 GLX_GREEN_SIZE,    8,
                                 GLX_BLUE_SIZE,     8,
                                 GLX_DOUBLEBUFFER,  True};
  if (samples > 0) fb_attribs.insert(fb_attribs.end(), {GLX_SAMPLE_BUFFERS, 1, GLX_SAMPLES, samples});
  fb_attribs.push_back(None);
  int n = 0;
  GLXFBConfig* configs = glXChooseFBConfig(dpy, DefaultScreen(dpy), fb_attribs.data(), &n);
  if (!configs || n < 1) {
    fprintf(stderr, "probe_glx: no GLX config\n");
    return 2;
  }
  XVisualInfo* vi = glXGetVisualFromFBConfig(dpy, configs[0]);
  XSetWindowAttributes swa{};
  swa.colormap = XCreateColormap(dpy, RootWindow(dpy, vi->screen), vi->visual, AllocNone);
  Window win = XCreateWindow(dpy, RootWindow(dpy, vi->screen), 0, 0, args.width, args.height, 0, vi->depth, InputOutput,
                             vi->visual, CWColormap, &swa);
  XMapWindow(dpy, win);
  using CreateAttribs = GLXContext (*)(Display*, GLXFBConfig, GLXContext, Bool, const int*);
  auto create = reinterpret_cast<CreateAttribs>(glXGetProcAddressARB((const GLubyte*)"glXCreateContextAttribsARB"));
  const int ctx_attribs[] = {
      GLX_CONTEXT_MAJOR_VERSION_ARB,    3,   GLX_CONTEXT_MINOR_VERSION_ARB, 3, GLX_CONTEXT_PROFILE_MASK_ARB,
      GLX_CONTEXT_CORE_PROFILE_BIT_ARB, None};
  GLXContext ctx = create ? create(dpy, configs[0], nullptr, True, ctx_attribs) : nullptr;
  if (!ctx) {
    fprintf(stderr, "probe_glx: cannot create a GL 3.3 core context\n");
    return 2;
  }
  glXMakeCurrent(dpy, win, ctx);
  GlFns gl;
  if (const char* missing = gl.load([](const char* n) { return (void*)glXGetProcAddressARB((const GLubyte*)n); })) {
    fprintf(stderr, "probe_glx: no %s\n", missing);
    return 2;
  }
  SlantedTriangle triangle;
  const bool slanted = want_slanted && triangle.make(gl);
  if (want_slanted && !slanted) {
    fprintf(stderr, "probe_glx: the triangle's program does not link\n");
    return 2;
  }
  BlitThrough blit;
  if (want_blit && !blit.make(args.width, args.height)) {
    fprintf(stderr, "probe_glx: no framebuffer objects\n");
    return 2;
  }
  int rc = run_known_scene(
      gl, ShaderDialect::kGlsl330Core, args, [&] { glXSwapBuffers(dpy, win); },
      [&] {
        if (slanted) triangle.draw(gl);
        if (want_blit) blit.run();
      });
  if (rc == 0 && swapped_out) {
    std::vector<uint8_t> swapped(static_cast<size_t>(args.width) * args.height * 4);
    glFinish();
    glReadPixels(0, 0, args.width, args.height, GL_RGBA, GL_UNSIGNED_BYTE, swapped.data());
    if (!write_ppm(swapped_out, swapped, args.width, args.height)) rc = 3;
  }
  GLint window_samples = -1, double_buffered = -1;
  GLboolean double_buffered_bool = GL_FALSE;
  glGetIntegerv(GL_SAMPLES, &window_samples);
  glGetIntegerv(GL_DOUBLEBUFFER, &double_buffered);
  glGetBooleanv(GL_DOUBLEBUFFER, &double_buffered_bool);
  if (const GLenum error = glGetError(); rc == 0 && error != GL_NO_ERROR) {
    fprintf(stderr, "probe_glx: GL error 0x%04x\n", error);
    rc = 4;
  }
  if (rc == 0 && samples > 0 && window_samples != samples) {
    fprintf(stderr, "probe_glx: the window answers %d samples, made with %d\n", window_samples, samples);
    rc = 5;
  }
  if (rc == 0 && (double_buffered != 1 || double_buffered_bool != GL_TRUE)) {
    fprintf(stderr, "probe_glx: the window answers GL_DOUBLEBUFFER %d (%d as a boolean), made double-buffered\n",
            double_buffered, double_buffered_bool);
    rc = 5;
  }
  glXMakeCurrent(dpy, None, nullptr);
  glXDestroyContext(dpy, ctx);
  XDestroyWindow(dpy, win);
  XFree(vi);
  XFree(configs);
  XCloseDisplay(dpy);
  return rc;
}
