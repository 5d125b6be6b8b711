// The draw-call benchmark load: --draws N tiny draws per frame (default 20000) alternating
// between --passes P programs in runs of --run R draws. Prints the mean CPU-side frame time.
// Linked directly so that the cost measured is the driver's and the shim's, not a loader's.
#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GL/glext.h>
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "common/egl_setup.hpp"

static double now_s() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

int main(int argc, char** argv) {
  int draws = 20000, passes = 1, run = 20000, frames = 30, warmup = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!strcmp(argv[i], "--draws"))
      draws = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--passes"))
      passes = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--run"))
      run = atoi(argv[i + 1]);
    else if (!strcmp(argv[i], "--frames"))
      frames = atoi(argv[i + 1]);
  }
  if (passes < 1) passes = 1;
  if (run < 1) run = 1;
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_drawheavy", egl, ContextKind::kCore45, 64, 64, &w)) return 2;
  std::vector<GLuint> programs;
  for (int p = 0; p < passes; ++p) {
    char fs[200];
    snprintf(fs, sizeof fs, "#version 330 core\nout vec4 c;\nvoid main(){ c = vec4(%d.0/%d.0, 0.5, 0.5, 1.0); }\n", p,
             passes);
    const char* vs = "#version 330 core\nlayout(location=0) in vec2 p;\nvoid main(){ gl_Position = vec4(p,0,1); }\n";
    const char* fsp = fs;
    GLuint prog = glCreateProgram();
    GLuint s1 = glCreateShader(GL_VERTEX_SHADER), s2 = glCreateShader(GL_FRAGMENT_SHADER);
    glShaderSource(s1, 1, &vs, nullptr);
    glShaderSource(s2, 1, &fsp, nullptr);
    glCompileShader(s1);
    glCompileShader(s2);
    glAttachShader(prog, s1);
    glAttachShader(prog, s2);
    glLinkProgram(prog);
    programs.push_back(prog);
  }
  // A one-pixel triangle: the driver's per-draw CPU cost dominates, as in a draw-heavy game.
  const float tri[] = {0, 0, 0.03f, 0, 0, 0.03f};
  GLuint vao, vbo;
  glGenVertexArrays(1, &vao);
  glBindVertexArray(vao);
  glGenBuffers(1, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof tri, tri, GL_STATIC_DRAW);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, nullptr);
  glEnableVertexAttribArray(0);
  double total = 0;
  for (int f = 0; f < warmup + frames; ++f) {
    double t0 = now_s();
    glClear(GL_COLOR_BUFFER_BIT);
    for (int d = 0; d < draws; ++d) {
      if (d % run == 0) glUseProgram(programs[(d / run) % passes]);
      glDrawArrays(GL_TRIANGLES, 0, 3);
    }
    eglSwapBuffers(w.display, w.surface);
    glFinish();
    if (f >= warmup) total += now_s() - t0;
  }
  printf("frame_ms %.4f draws %d passes %d run %d\n", 1e3 * total / frames, draws, passes, run);
  return 0;
}
