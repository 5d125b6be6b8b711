#include "bench.h"

#include <GL/glew.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

namespace demo {
namespace {

const char* const kKnobNames[kKnobCount] = {"resolution", "base shading", "reflections", "shadows", "metals",
                                            "antialiasing"};

double process_cpu_ms() {  // llvmpipe renders on this process's threads
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

struct Timing {
  double wall_ms = 0.0, min_wall_ms = 1e300, cpu_ms = 0.0;  // per frame
};

Timing time_frames(Renderer& renderer, GlContext& context, const Config& config, const Options& o) {
  const auto time_of = [&](long i) { return static_cast<double>(o.start_frame + i) / o.fps; };
  for (long warm_up = 0; warm_up < 2; ++warm_up) {  // first use allocates targets
    renderer.render(config, time_of(0));
    context.swap_buffers();
  }
  glFinish();
  Timing t;
  const double cpu_begin = process_cpu_ms();
  for (long i = 0; i < o.frames; ++i) {
    const auto begin = std::chrono::steady_clock::now();
    renderer.render(config, time_of(i));
    context.swap_buffers();
    glFinish();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
    t.wall_ms += ms;
    t.min_wall_ms = std::min(t.min_wall_ms, ms);
  }
  const auto frames = static_cast<double>(o.frames);
  t.wall_ms /= frames;
  t.cpu_ms = (process_cpu_ms() - cpu_begin) / frames;
  return t;
}

}  // namespace

void run_bench(Renderer& renderer, GlContext& context, const Scene& scene, const Options& o) {
  const FrameDraws draws = renderer.render(Config::best(), static_cast<double>(o.start_frame) / o.fps);
  const Timing best = time_frames(renderer, context, Config::best(), o);
  const Timing cheapest = time_frames(renderer, context, Config::cheapest(), o);
  std::printf("| scene | triangles | objects | draws/frame | best: wall ms (min) | best: CPU ms | cheapest: wall ms (min) "
              "| cheapest: CPU ms | CPU best/cheapest |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::printf("| %s | %.1fk | %zu | %d | %.0f (%.0f) | %.0f | %.0f (%.0f) | %.0f | %.2f |\n\n", scene.name.c_str(),
              static_cast<double>(scene.triangle_count()) / 1000.0, scene.objects.size(), draws.total(), best.wall_ms,
              best.min_wall_ms, best.cpu_ms, cheapest.wall_ms, cheapest.min_wall_ms, cheapest.cpu_ms,
              best.cpu_ms / cheapest.cpu_ms);

  std::printf("| %s: best but one knob at its cheapest | wall ms | CPU ms | CPU vs best |\n|---|---:|---:|---:|\n",
              scene.name.c_str());
  for (int k = 0; k < kKnobCount; ++k) {
    Config config = Config::best();
    config.level[k] = kLevelCount - 1;
    const Timing t = time_frames(renderer, context, config, o);
    std::printf("| %s (%s) | %.0f | %.0f | %.2f |\n", kKnobNames[k], format_config(config).c_str(), t.wall_ms, t.cpu_ms,
                t.cpu_ms / best.cpu_ms);
  }
  std::printf("\n(%dx%d, %s, %ld timed frames per row from frame %ld at %.0f fps after 2 warm-up frames, detail %.3g; "
              "wall clock includes glFinish; CPU = this process, where llvmpipe renders)\n",
              o.width, o.height, context.kind(), o.frames, o.start_frame, o.fps, static_cast<double>(o.detail));
}

}  // namespace demo
