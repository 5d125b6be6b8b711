// The paper's demo renderer: renders a scene's camera path at a forced configuration,
// optionally dumping frames, printing its statistics, or timing its extreme configurations.
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>

#include "bench.hpp"
#include "context.hpp"
#include "frame_stats.hpp"
#include "image_dump.hpp"
#include "options.hpp"
#include "renderer.hpp"
#include "scenes/registry.hpp"

namespace {

// One frame in every configuration, for ground truth over the whole space (the governor's error
// estimates against the images they estimate): the frames are functions of time only, so each
// image is the one a run at that configuration draws at that frame.
int dump_all_configs(demo::Renderer& renderer, demo::GlContext& context, const demo::Scene& scene,
                     const demo::Options& o) {
  if (o.dump_dir.empty()) {
    std::fprintf(stderr, "demo: --all-configs needs --dump DIR\n");
    return 2;
  }
  const double time = static_cast<double>(o.start_frame) / o.fps;
  for (int index = 0; index < demo::kConfigCount; ++index) {
    const demo::Config config = demo::Config::from_index(index);
    renderer.render(config, time);
    const std::string path = demo::dump_path(o.dump_dir, scene.name, demo::format_config(config), o.start_frame);
    const std::string error = demo::write_rgb_image(path, o.width, o.height, renderer.read_pixels());
    if (!error.empty()) {
      std::fprintf(stderr, "demo: %s\n", error.c_str());
      return 1;
    }
    context.swap_buffers();
  }
  std::fprintf(stderr, "demo: frame %ld of %s at %dx%d in all %d configurations on %s, into %s\n", o.start_frame,
               scene.name.c_str(), o.width, o.height, demo::kConfigCount, context.kind(), o.dump_dir.c_str());
  return 0;
}

int run(const demo::Options& o) {
  const demo::Scene scene = *demo::make_scene(o.scene, o.detail);
  auto context = o.glx ? demo::create_glx_context(o.width, o.height) : demo::create_egl_context(o.width, o.height);
  demo::Renderer renderer(scene, o.width, o.height, o.shadow_size);

  if (o.stats) {
    const demo::FrameDraws draws = renderer.render(o.config, static_cast<double>(o.start_frame) / o.fps);
    demo::print_stats_header(std::cout);
    demo::print_stats_row(std::cout, scene, draws);
    return 0;
  }
  if (o.bench) {
    demo::run_bench(renderer, *context, scene, o);
    return 0;
  }

  if (!o.dump_dir.empty()) std::filesystem::create_directories(o.dump_dir);
  if (o.all_configs) return dump_all_configs(renderer, *context, scene, o);
  const std::string config_text = demo::format_config(o.config);
  long dumped = 0;
  for (long i = 0; i < o.frames; ++i) {
    const long frame = o.start_frame + i;
    renderer.render(o.config, static_cast<double>(frame) / o.fps);
    if (!o.dump_dir.empty() && i % o.dump_every == 0) {
      const std::string path = demo::dump_path(o.dump_dir, scene.name, config_text, frame);
      const std::string error = demo::write_rgb_image(path, o.width, o.height, renderer.read_pixels());
      if (!error.empty())
        std::fprintf(stderr, "demo: %s\n", error.c_str());
      else
        ++dumped;
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
