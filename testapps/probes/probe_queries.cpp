// An app with queries of its own, on the very targets glbudget uses and others, and with a
// pending GL error of its own. It checks every answer itself and exits 1 on a wrong one:
//  - GL_FRAGMENT_SHADER_INVOCATIONS_ARB around pass B: 3 * 256 fragments;
//  - GL_SAMPLES_PASSED around pass A: 2 * W/2 * H samples; GL_TIME_ELAPSED around the frame;
//  - GL_CURRENT_QUERY of GL_VERTEX_SHADER_INVOCATIONS_ARB is 0 while the app has none active;
//  - an INVALID_ENUM raised before a frame is still the first glGetError after it.
#include <cstdio>

#include "common/egl_setup.hpp"
#include "common/known_scene.hpp"

static int failures = 0;
static void expect(bool ok, const char* what, long long got, long long want) {
  if (ok) return;
  fprintf(stderr, "probe_queries: %s: got %lld, want %lld\n", what, got, want);
  ++failures;
}

int main(int argc, char** argv) {
  ProbeArgs args = parse_probe_args(argc, argv);
  EglFns egl;
  EglWindow w;
  if (!open_current_window("probe_queries", egl, ContextKind::kCore45, args.width, args.height, &w)) return 2;
  GlFns gl;
  gl.load([&](const char* n) { return (void*)egl.GetProcAddress(n); });
  KnownScene scene(gl, ShaderDialect::kGlsl330Core, args.width, args.height);
  if (!scene.ok()) return 2;
  GLuint q[3];
  gl.GenQueries(3, q);
  for (int f = 0; f < args.frames; ++f) {
    gl.Enable(0xFFFF);  // deliberately invalid: GL_INVALID_ENUM stays pending through the frame
    gl.BeginQuery(GL_TIME_ELAPSED, q[2]);
    gl.ClearColor(0, 0, 0, 1);
    gl.Clear(GL_COLOR_BUFFER_BIT);
    gl.BeginQuery(GL_SAMPLES_PASSED, q[1]);
    scene.draw_pass_a();
    gl.EndQuery(GL_SAMPLES_PASSED);
    GLint current = -1;
    gl.GetQueryiv(GL_VERTEX_SHADER_INVOCATIONS_ARB, GL_CURRENT_QUERY, &current);
    expect(current == 0, "GL_CURRENT_QUERY of vertex invocations", current, 0);
    gl.BeginQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, q[0]);
    gl.GetQueryiv(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, GL_CURRENT_QUERY, &current);
    expect(current == (GLint)q[0], "GL_CURRENT_QUERY of the app's own query", current, q[0]);
    scene.draw_pass_b();
    gl.EndQuery(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
    gl.EndQuery(GL_TIME_ELAPSED);
    GLenum err = gl.GetError();
    expect(err == GL_INVALID_ENUM, "first glGetError after the frame", err, GL_INVALID_ENUM);
    err = gl.GetError();
    expect(err == GL_NO_ERROR, "second glGetError after the frame", err, GL_NO_ERROR);
    egl.SwapBuffers(w.display, w.surface);
    GLuint fragments = 0, samples = 0, ns = 0;
    gl.GetQueryObjectuiv(q[0], GL_QUERY_RESULT, &fragments);
    gl.GetQueryObjectuiv(q[1], GL_QUERY_RESULT, &samples);
    gl.GetQueryObjectuiv(q[2], GL_QUERY_RESULT, &ns);
    expect(fragments == 768, "app's fragment-invocations query", fragments, 768);
    expect(samples == GLuint(args.width * args.height), "app's samples-passed query", samples,
           args.width * args.height);
    expect(ns > 0, "app's time-elapsed query", ns, 1);
    expect(gl.GetError() == GL_NO_ERROR, "glGetError after the swap", 1, 0);
  }
  if (!write_ppm(args.out, scene.read_rgba(), args.width, args.height)) return 3;
  return failures ? 1 : 0;
}
