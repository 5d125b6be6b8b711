// The frame loop most probes share: draw the known scene, swap, write the last image.
#pragma once
#include <cstdio>
#include <functional>

#include "known_scene.hpp"

// `after_draw`, if any, draws more into each frame after the scene (before it is read).
inline int run_known_scene(const GlFns& gl, ShaderDialect dialect, const ProbeArgs& args,
                           const std::function<void()>& swap, const std::function<void()>& after_draw = {}) {
  KnownScene scene(gl, dialect, args.width, args.height);
  if (!scene.ok()) {
    fprintf(stderr, "probe: %s\n", scene.error().c_str());
    return 2;
  }
  std::vector<uint8_t> image;
  for (int f = 0; f < args.frames; ++f) {
    scene.draw_frame(f);
    if (after_draw) after_draw();
    // Read before the last swap: after a swap the back buffer's contents are undefined.
    if (f + 1 == args.frames) image = scene.read_rgba();
    swap();
  }
  if (!write_ppm(args.out, image, args.width, args.height)) {
    fprintf(stderr, "probe: cannot write %s\n", args.out.c_str());
    return 3;
  }
  return 0;
}
