// Each of the six knobs changes the image, and the frame's work where the pipeline statistics
// can see it (fragments, draws); in-shader knobs reach the driver as #defines and uniforms.
#include <catch2/catch.hpp>

#include "render_fixture.hpp"
#include "scenes/registry.hpp"

using demo::Config;
using demo::Knob;
using demo::Pass;
using demo_test::render;

namespace {

constexpr double kTime = 1.0;

Config with(Knob knob, int level) {
  Config c = Config::best();
  c[knob] = level;
  return c;
}

GLint uniform_value(GLuint program, const char* name) {
  GLint value = -1;
  glGetUniformiv(program, glGetUniformLocation(program, name), &value);
  return value;
}

struct Fixture {
  Fixture()
      : context(demo_test::gl_context()),
        scene(*demo::make_scene("hall", 0.05f)),
        renderer(scene, demo_test::kWidth, demo_test::kHeight) {}
  demo::GlContext& context;
  demo::Scene scene;
  demo::Renderer renderer;
};

}  // namespace

TEST_CASE_METHOD(Fixture, "resolution: fewer scene fragments at 80% and 60% scale", "[demo][knobs]") {
  const auto f0 = render(renderer, with(Knob::Resolution, 0), kTime);
  const auto f1 = render(renderer, with(Knob::Resolution, 1), kTime);
  const auto f2 = render(renderer, with(Knob::Resolution, 2), kTime);
  for (Pass pass : {Pass::Base, Pass::Metals, Pass::Reflections}) {
    INFO(demo::pass_name(pass));
    CHECK(f1[pass].fragments < f0[pass].fragments);
    CHECK(f2[pass].fragments < f1[pass].fragments);
  }
  // Full-screen passes scale with the pixel count: 0.6^2 = 0.36 of the pixels (llvmpipe
  // counts invocations by blocks, so partly covered blocks at the edges add a little).
  const double ratio = static_cast<double>(f2[Pass::Reflections].fragments) / f0[Pass::Reflections].fragments;
  CHECK(ratio > 0.33);
  CHECK(ratio < 0.42);
  CHECK(f2[Pass::Upscale].fragments == f0[Pass::Upscale].fragments);  // output stays at window size
  CHECK(f0.pixels != f1.pixels);
  CHECK(f1.pixels != f2.pixels);
}

TEST_CASE_METHOD(Fixture, "shadows: the shadow map's fragments follow its resolution", "[demo][knobs]") {
  const auto f0 = render(renderer, with(Knob::Shadows, 0), kTime);
  const auto f1 = render(renderer, with(Knob::Shadows, 1), kTime);
  const auto f2 = render(renderer, with(Knob::Shadows, 2), kTime);
  // 2048^2 : 1024^2 : 512^2 texels: 4x per level for large triangles; llvmpipe counts
  // invocations by blocks, so small triangles in the smaller maps count a little extra.
  CHECK(f0[Pass::Shadows].fragments > 2.5 * f1[Pass::Shadows].fragments);
  CHECK(f1[Pass::Shadows].fragments > 2.5 * f2[Pass::Shadows].fragments);
  CHECK(f0[Pass::Shadows].vertices == f2[Pass::Shadows].vertices);
  CHECK(f0[Pass::Base].fragments == f2[Pass::Base].fragments);
  CHECK(f0.pixels != f1.pixels);
  CHECK(f1.pixels != f2.pixels);
}

TEST_CASE_METHOD(Fixture, "reflections: 64 samples 9 taps, 16 samples 1 tap, then no pass", "[demo][knobs]") {
  const auto f0 = render(renderer, with(Knob::Reflections, 0), kTime);
  CHECK(uniform_value(f0[Pass::Reflections].program, "u_samples") == 64);
  CHECK(uniform_value(f0[Pass::Reflections].program, "u_kernel_taps") == 9);
  const auto f1 = render(renderer, with(Knob::Reflections, 1), kTime);
  CHECK(uniform_value(f1[Pass::Reflections].program, "u_samples") == 16);
  CHECK(uniform_value(f1[Pass::Reflections].program, "u_kernel_taps") == 1);
  const auto f2 = render(renderer, with(Knob::Reflections, 2), kTime);
  REQUIRE(f0[Pass::Reflections].ran);
  CHECK(f1[Pass::Reflections].fragments == f0[Pass::Reflections].fragments);
  CHECK_FALSE(f2[Pass::Reflections].ran);
  CHECK(f2.draws.total() == f0.draws.total() - 1);
  CHECK(f0.pixels != f1.pixels);
  CHECK(f1.pixels != f2.pixels);
}

TEST_CASE_METHOD(Fixture, "base shading: microfacet, improved point lights, cheap specular", "[demo][knobs]") {
  std::vector<demo_test::RenderedFrame> frames;
  for (int level = 0; level < 3; ++level) {
    frames.push_back(render(renderer, with(Knob::BaseShading, level), kTime));
    const std::string define = "#define SHADING_MODEL " + std::to_string(2 - level) + "\n";
    CHECK(demo_test::fragment_source(frames.back()[Pass::Base].program).find(define) != std::string::npos);
  }
  CHECK(frames[0][Pass::Base].fragments == frames[2][Pass::Base].fragments);  // same surfaces, cheaper shader
  CHECK(frames[0].pixels != frames[1].pixels);
  CHECK(frames[1].pixels != frames[2].pixels);
  CHECK(frames[0].pixels != frames[2].pixels);
}

TEST_CASE_METHOD(Fixture, "metals: 60, 6 and 2 importance samples", "[demo][knobs]") {
  std::vector<demo_test::RenderedFrame> frames;
  for (int level = 0; level < 3; ++level) {
    frames.push_back(render(renderer, with(Knob::Metals, level), kTime));
    const char* samples[] = {"60", "6", "2"};
    const std::string define = std::string("#define METAL_SAMPLES ") + samples[level] + "\n";
    REQUIRE(frames.back()[Pass::Metals].ran);
    CHECK(demo_test::fragment_source(frames.back()[Pass::Metals].program).find(define) != std::string::npos);
  }
  CHECK(frames[0][Pass::Metals].fragments == frames[2][Pass::Metals].fragments);
  CHECK(frames[0][Pass::Base].fragments == frames[2][Pass::Base].fragments);
  CHECK(frames[0].pixels != frames[1].pixels);
  CHECK(frames[1].pixels != frames[2].pixels);
}

TEST_CASE_METHOD(Fixture, "antialiasing: FXAA 32 steps, 2 steps, then no pass", "[demo][knobs]") {
  const auto f0 = render(renderer, with(Knob::Antialiasing, 0), kTime);
  const auto f1 = render(renderer, with(Knob::Antialiasing, 1), kTime);
  const auto f2 = render(renderer, with(Knob::Antialiasing, 2), kTime);
  CHECK(demo_test::fragment_source(f0[Pass::Antialiasing].program).find("#define FXAA_STEPS 32\n") !=
        std::string::npos);
  CHECK(demo_test::fragment_source(f1[Pass::Antialiasing].program).find("#define FXAA_STEPS 2\n") != std::string::npos);
  // One invocation per window pixel, give or take llvmpipe's block counting at the edges.
  const auto pixels = static_cast<double>(demo_test::kWidth * demo_test::kHeight);
  CHECK(f0[Pass::Antialiasing].fragments >= pixels);
  CHECK(f0[Pass::Antialiasing].fragments < 1.1 * pixels);
  CHECK(f1[Pass::Antialiasing].fragments == f0[Pass::Antialiasing].fragments);
  CHECK_FALSE(f2[Pass::Antialiasing].ran);
  CHECK(f0.pixels != f1.pixels);
  CHECK(f1.pixels != f2.pixels);
}

TEST_CASE("valley: the reflections and metals levels do not change its image", "[demo][knobs]") {
  demo_test::gl_context();
  const demo::Scene valley = *demo::make_scene("valley", 0.05f);
  demo::Renderer renderer(valley, demo_test::kWidth, demo_test::kHeight);
  const auto reference = render(renderer, Config::best(), kTime);
  CHECK_FALSE(reference[Pass::Metals].ran);
  CHECK_FALSE(reference[Pass::Reflections].ran);
  for (int reflections = 0; reflections < 3; ++reflections) {
    for (int metals = 0; metals < 3; ++metals) {
      Config c = Config::best();
      c[Knob::Reflections] = reflections;
      c[Knob::Metals] = metals;
      INFO(demo::format_config(c));
      const auto frame = render(renderer, c, kTime);
      CHECK(frame.pixels == reference.pixels);
      CHECK(frame.draws.draws == reference.draws.draws);
    }
  }
  // ...while the other knobs do.
  CHECK(render(renderer, with(Knob::Shadows, 2), kTime).pixels != reference.pixels);
}
