// The paper's demo renderer: renders a scene's camera path at a forced configuration,
// optionally dumping frames, printing its statistics, or timing its extreme configurations.
#include <GL/glew.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "context.h"
#include "frame_stats.h"
#include "image_dump.h"
#include "options.h"
#include "renderer.h"
#include "scenes/registry.h"

namespace {

// Mean and minimum wall-clock milliseconds per frame (render + glFinish) over `frames` frames.
struct Timing {
  double mean_ms, min_ms;
};
Timing time_frames(demo::Renderer& renderer, demo::GlContext& context, const demo::Config& config,
                   const demo::Options& o) {
  for (long warm_up = 0; warm_up < 2; ++warm_up) {  // first use compiles and allocates
    renderer.render(config, static_cast<double>(o.start_frame) / o.fps);
    context.swap_buffers();
  }
  glFinish();
  double total = 0.0, best = 1e300;
  for (long i = 0; i < o.frames; ++i) {
    const auto begin = std::chrono::steady_clock::now();
    renderer.render(config, static_cast<double>(o.start_frame + i) / o.fps);
    context.swap_buffers();
    glFinish();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
    total += ms;
    best = std::min(best, ms);
  }
  return {total / static_cast<double>(o.frames), best};
}

int run(const demo::Options& o) {
  const demo::Scene scene = *demo::make_scene(o.scene, o.detail);
  auto context = o.glx ? demo::create_glx_context(o.width, o.height) : demo::create_egl_context(o.width, o.height);
  demo::Renderer renderer(scene, o.width, o.height);

  if (o.stats) {
    const demo::FrameDraws draws = renderer.render(o.config, static_cast<double>(o.start_frame) / o.fps);
    demo::print_stats_header(std::cout);
    demo::print_stats_row(std::cout, scene, draws);
    return 0;
  }
  if (o.bench) {
    const demo::FrameDraws draws = renderer.render(demo::Config::best(), static_cast<double>(o.start_frame) / o.fps);
    const Timing best = time_frames(renderer, *context, demo::Config::best(), o);
    const Timing cheapest = time_frames(renderer, *context, demo::Config::cheapest(), o);
    std::printf("| scene | triangles | objects | draws/frame (best) | best ms/frame | cheapest ms/frame | best/cheapest |\n"
                "|---|---:|---:|---:|---:|---:|---:|\n");
    std::printf("| %s | %.1fk | %zu | %d | %.1f (min %.1f) | %.1f (min %.1f) | %.2f |\n", scene.name.c_str(),
                static_cast<double>(scene.triangle_count()) / 1000.0, scene.objects.size(), draws.total(),
                best.mean_ms, best.min_ms, cheapest.mean_ms, cheapest.min_ms, best.mean_ms / cheapest.mean_ms);
    std::printf("(%dx%d, %s, %ld frames from frame %ld at %.0f fps, detail %.3g, wall clock incl. glFinish)\n", o.width,
                o.height, context->kind(), o.frames, o.start_frame, o.fps, static_cast<double>(o.detail));
    return 0;
  }

  if (!o.dump_dir.empty()) std::filesystem::create_directories(o.dump_dir);
  const std::string config_text = demo::format_config(o.config);
  long dumped = 0;
  for (long i = 0; i < o.frames; ++i) {
    const long frame = o.start_frame + i;
    renderer.render(o.config, static_cast<double>(frame) / o.fps);
    if (!o.dump_dir.empty() && i % o.dump_every == 0) {
      const std::string path = demo::dump_path(o.dump_dir, scene.name, config_text, frame);
      const std::string error = demo::write_rgb_image(path, o.width, o.height, renderer.read_pixels());
      if (!error.empty()) std::fprintf(stderr, "demo: %s\n", error.c_str());
      else ++dumped;
    }
    context->swap_buffers();
  }
  std::fprintf(stderr, "demo: rendered %ld frames of %s at %dx%d, config %s, on %s", o.frames, scene.name.c_str(),
               o.width, o.height, config_text.c_str(), context->kind());
  if (dumped) std::fprintf(stderr, "; %ld images in %s", dumped, o.dump_dir.c_str());
  std::fprintf(stderr, "\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  const demo::Options options = demo::parse_options(argc, argv);
  if (options.help) {
    std::fputs(demo::usage(), stdout);
    return 0;
  }
  try {
    return run(options);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "demo: %s\n", error.what());
    return 1;
  }
}
