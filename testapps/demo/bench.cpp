#include "bench.hpp"

#include <GL/glew.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <vector>

namespace demo {
namespace {

const char* const kKnobNames[kKnobCount] = {"resolution", "base shading", "reflections",
                                            "shadows",    "metals",       "antialiasing"};

double process_cpu_ms() {  // llvmpipe renders on this process's threads
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

struct Timing {
  double wall_ms = 0.0, min_wall_ms = 1e300, cpu_ms = 0.0;  // per frame
};

// Times the configurations round-robin, one frame each per round, so that a change of load
// on a shared machine affects all of them alike and their ratios stay comparable.
std::vector<Timing> time_round_robin(Renderer& renderer, GlContext& context, const std::vector<Config>& configs,
                                     const Options& o) {
  const auto time_of = [&](long i) { return static_cast<double>(o.start_frame + i) / o.fps; };
  for (const Config& config : configs) {  // first use of a configuration allocates targets
    renderer.render(config, time_of(0));
    context.swap_buffers();
  }
  glFinish();
  std::vector<Timing> timings(configs.size());
  for (long i = 0; i < o.frames; ++i) {
    for (size_t c = 0; c < configs.size(); ++c) {
      const double cpu_begin = process_cpu_ms();
      const auto begin = std::chrono::steady_clock::now();
      renderer.render(configs[c], time_of(i));
      context.swap_buffers();
      glFinish();
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
      timings[c].cpu_ms += process_cpu_ms() - cpu_begin;
      timings[c].wall_ms += ms;
      timings[c].min_wall_ms = std::min(timings[c].min_wall_ms, ms);
    }
  }
  for (Timing& t : timings) {
    t.wall_ms /= static_cast<double>(o.frames);
    t.cpu_ms /= static_cast<double>(o.frames);
  }
  return timings;
}

}  // namespace

void run_bench(Renderer& renderer, GlContext& context, const Scene& scene, const Options& o) {
  const FrameDraws draws = renderer.render(Config::best(), static_cast<double>(o.start_frame) / o.fps);
  // Best, cheapest, then the best with each knob alone at its cheapest level.
  std::vector<Config> configs{Config::best(), Config::cheapest()};
  for (int k = 0; k < kKnobCount; ++k) {
    configs.push_back(Config::best());
    configs.back().level[k] = kLevelCount - 1;
  }
  const std::vector<Timing> timings = time_round_robin(renderer, context, configs, o);
  const Timing& best = timings[0];
  const Timing& cheapest = timings[1];
  std::printf(
      "| scene | triangles | objects | draws/frame | best: wall ms (min) | best: CPU ms | cheapest: wall ms (min) "
      "| cheapest: CPU ms | CPU best/cheapest |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  std::printf("| %s | %.1fk | %zu | %d | %.0f (%.0f) | %.0f | %.0f (%.0f) | %.0f | %.2f |\n\n", scene.name.c_str(),
              static_cast<double>(scene.triangle_count()) / 1000.0, scene.objects.size(), draws.total(), best.wall_ms,
              best.min_wall_ms, best.cpu_ms, cheapest.wall_ms, cheapest.min_wall_ms, cheapest.cpu_ms,
              best.cpu_ms / cheapest.cpu_ms);

  std::printf("| %s: best but one knob at its cheapest | wall ms | CPU ms | CPU vs best |\n|---|---:|---:|---:|\n",
              scene.name.c_str());
  for (int k = 0; k < kKnobCount; ++k) {
    const Timing& t = timings[static_cast<size_t>(2 + k)];
    std::printf("| %s (%s) | %.0f | %.0f | %.2f |\n", kKnobNames[k],
                format_config(configs[static_cast<size_t>(2 + k)]).c_str(), t.wall_ms, t.cpu_ms,
                t.cpu_ms / best.cpu_ms);
  }
  std::printf(
      "\n(%dx%d, %s, %ld timed frames per row from frame %ld at %.0f fps, rows interleaved frame by frame after one "
      "warm-up frame each, detail %.3g; "
      "wall clock includes glFinish; CPU = this process, where llvmpipe renders)\n",
      o.width, o.height, context.kind(), o.frames, o.start_frame, o.fps, static_cast<double>(o.detail));
}

}  // namespace demo
