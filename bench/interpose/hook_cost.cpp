// The shim's own CPU cost per intercepted draw call, in isolation from the driver: the
// generated glDrawArrays wrapper is called with a do-nothing "driver" behind it, and compared
// with calling that driver directly through a function pointer (what an app does without the
// shim), in the same process. The end-to-end cost with a real driver, including what
// llvmpipe spends on counting, is draw_overhead.py's job.
#include <time.h>

#include <algorithm>
#include <cstdio>

#include "draw_count.hpp"
#include "hook_table.hpp"

extern "C" void glDrawArrays(GLenum mode, GLint first, GLsizei count);  // the shim's wrapper

namespace {
volatile long g_sink;
__attribute__((noinline)) void fake_driver_draw(GLenum mode, GLint first, GLsizei count) {
  g_sink = g_sink + mode + first + count;
}
using DrawFn = void (*)(GLenum, GLint, GLsizei);
DrawFn volatile g_driver = &fake_driver_draw;  // volatile: the call stays indirect
DrawFn volatile g_shim = &glDrawArrays;

double now_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return ts.tv_sec * 1e9 + ts.tv_nsec;
}

// Best of several runs of `calls` calls: the least disturbed estimate of the cost.
template <typename F>
double ns_per_call(F call, long calls = 20'000'000, int runs = 7) {
  double best = 1e300;
  for (int r = 0; r < runs; ++r) {
    double t0 = now_ns();
    for (long i = 0; i < calls; ++i) call();
    best = std::min(best, (now_ns() - t0) / calls);
  }
  return best;
}
}  // namespace

int main() {
  using namespace glbudget;
  g_real[kHook_glDrawArrays] = reinterpret_cast<void*>(&fake_driver_draw);

  const double direct = ns_per_call([] { g_driver(GL_TRIANGLES, 0, 3); });

  DrawCounter same_pass;  // a segment is open for the bound program: the hot path
  same_pass.ready = true;
  t_draw = &same_pass;
  const double in_pass = ns_per_call([] { g_shim(GL_TRIANGLES, 0, 3); });

  t_draw = nullptr;  // no context current on this thread
  const double no_context = ns_per_call([] { g_shim(GL_TRIANGLES, 0, 3); });

  printf("glDrawArrays with a do-nothing driver, best of 7 x 20M calls\n");
  printf("%-40s%10s%10s%12s\n", "path", "ns/call", "ratio", "added ns");
  printf("%-40s%10.2f%10.3f%12s\n", "app -> driver (baseline)", direct, 1.0, "-");
  printf("%-40s%10.2f%10.3f%12.2f\n", "app -> shim -> driver, draw in pass", in_pass, in_pass / direct,
         in_pass - direct);
  printf("%-40s%10.2f%10.3f%12.2f\n", "app -> shim -> driver, no context", no_context, no_context / direct,
         no_context - direct);
  printf("batches counted: %llu\n", static_cast<unsigned long long>(same_pass.open_batches));
  return same_pass.open_batches > 0 ? 0 : 1;
}
