// Every one of the 729 configurations compiles and renders, on the scene that exercises every
// pass (subway: reflective floor, rigid and skinned metals).
#include <catch2/catch.hpp>

#include <algorithm>

#include "render_fixture.hpp"
#include "scenes/registry.hpp"

TEST_CASE("all 729 configurations render a non-blank frame without GL errors", "[demo][configurations]") {
  demo_test::gl_context();
  const demo::Scene scene = *demo::make_scene("subway", 0.01f);
  // A quarter of the usual frame: this renders 729 frames, a third of them with 2048^2 shadows.
  demo::Renderer renderer(scene, demo_test::kWidth / 2, demo_test::kHeight / 2);
  while (glGetError() != GL_NO_ERROR) {
  }
  int blank = 0, failed = 0;
  for (int index = 0; index < 729; ++index) {
    const demo::Config config = demo::Config::from_index(index);
    const demo::FrameDraws draws = renderer.render(config, 2.0);
    const std::vector<uint8_t> pixels = renderer.read_pixels();
    const auto [lo, hi] = std::minmax_element(pixels.begin(), pixels.end());
    if (*hi - *lo < 32) ++blank;
    if (glGetError() != GL_NO_ERROR) {
      ++failed;
      UNSCOPED_INFO("GL error in " << demo::format_config(config));
    }
    // shadows + base + metals + upscale always; reflections and antialiasing unless off.
    const int full_screen = 1 + (config[demo::Knob::Reflections] < 2) + (config[demo::Knob::Antialiasing] < 2);
    if (draws.total() != 2 * static_cast<int>(scene.objects.size()) + full_screen) ++failed;
  }
  CHECK(failed == 0);
  CHECK(blank == 0);
}
