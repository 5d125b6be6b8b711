// GpuSsim (interpose/quality: compute shaders) against the CPU path (glbudget::quality::ssim)
// on image pairs from 1x1 to 4096x4096 at scales 1, 2 and 4, in EGL surfaceless contexts
// (OpenGL 4.3+ core, and OpenGL ES 3.1+): agreement within 1e-4, identical images exactly 1,
// every piece of GL state it touches restored, poll() never blocking.
#include <GL/glcorearb.h>

#include <catch2/catch.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "egl_context.hpp"
#include "gl_texture.hpp"
#include "glbudget/quality/ssim.hpp"
#include "gpu_ssim.hpp"
#include "gpu_ssim_images.hpp"

using glbudget::GpuSsim;
using glbudget::cli::GlApi;
using glbudget::cli::GlTexture;
using glbudget::cli::HeadlessGlContext;
using namespace gpu_ssim_test;

namespace {

constexpr double kTolerance = 1e-4;

// One context and one GpuSsim per API for the whole program; released in the right context.
struct Gl {
  std::unique_ptr<HeadlessGlContext> context;
  std::unique_ptr<GpuSsim> gpu;
  ~Gl() {
    if (context) context->make_current();
    gpu.reset();
  }
};

Gl& gl(GlApi api) {
  static Gl contexts[2];
  Gl& g = contexts[api == GlApi::kDesktop ? 0 : 1];
  std::string why_not;
  if (!g.context) g.context = HeadlessGlContext::open(api, &why_not);
  INFO(why_not);
  REQUIRE(g.context);
  REQUIRE(g.context->make_current());
  if (!g.gpu) g.gpu = GpuSsim::create(&HeadlessGlContext::proc_address, &why_not);
  INFO(why_not);
  REQUIRE(g.gpu);
  return g;
}

template <typename T>
T entry(const char* name) {
  auto function = reinterpret_cast<T>(HeadlessGlContext::proc_address(name));
  REQUIRE(function);
  return function;
}

std::unique_ptr<GlTexture> upload(const Rgba8& image, GLenum internal_format = GL_RGBA8) {
  return std::make_unique<GlTexture>(&HeadlessGlContext::proc_address, image.width, image.height, internal_format,
                                     GL_RGBA, GL_UNSIGNED_BYTE, image.pixels.data());
}

double gpu_ssim(GpuSsim& gpu, const Rgba8& a, const Rgba8& b, int scale) {
  const auto texture_a = upload(a), texture_b = upload(b);
  return gpu.wait(gpu.submit(texture_a->name(), texture_b->name(), a.width, a.height, scale));
}

struct Pair {
  std::string name;
  int scale;
  std::function<Rgba8()> a, b;  // generated when the pair runs: the 4096x4096 ones are 64 MiB each
};

std::vector<Pair> pairs() {
  const auto frame_noise = [](int w, int h, float amplitude) {
    return [=] { return with_noise(frame(w, h), amplitude, 1); };
  };
  const auto same = [](std::function<Rgba8()> make) { return make; };
  return {
      {"frame vs noise +-12", 1, [] { return frame(640, 360); }, frame_noise(640, 360, 12)},
      {"frame vs noise +-12", 2, [] { return frame(640, 360); }, frame_noise(640, 360, 12)},
      {"frame vs noise +-12", 4, [] { return frame(640, 360); }, frame_noise(640, 360, 12)},
      {"frame vs camera moved 1 px", 1, [] { return frame(640, 360); }, [] { return frame(640, 360, 1.0f); }},
      {"frame vs banding, 8 levels", 1, [] { return frame(640, 360); }, [] { return banded(frame(640, 360), 8); }},
      {"frame vs checkerboard", 2, [] { return frame(640, 360); }, [] { return checkerboard(640, 360, 7, 0); }},
      {"frame vs render scale 1/2", 1, [] { return frame(1920, 1080); }, [] { return render_scaled(1920, 1080, 2); }},
      {"frame vs render scale 1/2", 4, [] { return frame(1920, 1080); }, [] { return render_scaled(1920, 1080, 2); }},
      {"frame vs 3x3 blur", 2, [] { return frame(1920, 1080); }, [] { return blur3(frame(1920, 1080)); }},
      {"frame vs noise +-16", 1, [] { return frame(4096, 4096); }, frame_noise(4096, 4096, 16)},
      {"identical frames", 1, [] { return frame(640, 360); }, same([] { return frame(640, 360); })},
      {"identical frames", 2, [] { return frame(1920, 1080); }, same([] { return frame(1920, 1080); })},
      {"odd size frame vs noise", 4, [] { return frame(101, 77); }, frame_noise(101, 77, 20)},
      {"noise vs noise", 1, [] { return noise(300, 200, 1); }, [] { return noise(300, 200, 2); }},
      {"horizontal vs vertical gradient", 1, [] { return gradient(256, 256, true); },
       [] { return gradient(256, 256, false); }},
      {"checkerboard moved 1 px", 1, [] { return checkerboard(640, 360, 6, 0); },
       [] { return checkerboard(640, 360, 6, 1); }},
      {"constant 100 vs 130", 1, [] { return constant(256, 256, 100, 100, 100); },
       [] { return constant(256, 256, 130, 130, 130); }},
      {"black vs white", 1, [] { return constant(64, 64, 0, 0, 0); }, [] { return constant(64, 64, 255, 255, 255); }},
      {"black vs black", 1, [] { return constant(64, 48, 0, 0, 0); }, [] { return constant(64, 48, 0, 0, 0); }},
      {"white vs white", 2, [] { return constant(33, 17, 255, 255, 255); },
       [] { return constant(33, 17, 255, 255, 255); }},
      {"identical 1x1", 1, [] { return noise(1, 1, 3); }, [] { return noise(1, 1, 3); }},
      {"different 1x1", 1, [] { return noise(1, 1, 3); }, [] { return noise(1, 1, 4); }},
      {"different 1x1", 4, [] { return noise(1, 1, 5); }, [] { return noise(1, 1, 6); }},
      {"random 7x5", 1, [] { return noise(7, 5, 7); }, [] { return noise(7, 5, 8); }},
      {"random 10x10", 2, [] { return noise(10, 10, 9); }, [] { return noise(10, 10, 10); }},
      {"random 11x11", 1, [] { return noise(11, 11, 11); }, [] { return noise(11, 11, 12); }},
      {"frame 11x11 vs noise", 1, [] { return frame(11, 11); }, frame_noise(11, 11, 30)},
      {"random 12x300", 1, [] { return noise(12, 300, 13); }, [] { return noise(12, 300, 14); }},
      {"frame 12x300 vs noise", 4, [] { return frame(12, 300); }, frame_noise(12, 300, 10)},
      {"4096x1 strip", 1, [] { return frame(4096, 1); }, frame_noise(4096, 1, 10)},
      {"1x77 column", 2, [] { return frame(1, 77); }, frame_noise(1, 77, 10)},
  };
}

// Runs every pair on one context; prints the table; returns the largest |GPU - CPU|.
double check_pairs(GlApi api, bool large) {
  GpuSsim& gpu = *gl(api).gpu;
  double worst = 0.0;
  std::printf("%-34s %10s %5s %13s %13s %9s\n", "pair", "size", "scale", "CPU", "GPU", "|diff|");
  for (const Pair& pair : pairs()) {
    const Rgba8 a = pair.a(), b = pair.b();
    if (!large && static_cast<long>(a.width) * a.height > 1000000) continue;
    const double cpu = glbudget::quality::ssim(a.luma().view(), b.luma().view(), {pair.scale, 0});
    const double gpu_value = gpu_ssim(gpu, a, b, pair.scale);
    const double diff = std::abs(gpu_value - cpu);
    worst = std::max(worst, diff);
    std::printf("%-34s %4dx%-5d %5d %13.9f %13.9f %9.1e\n", pair.name.c_str(), a.width, a.height, pair.scale, cpu,
                gpu_value, diff);
    CAPTURE(pair.name, a.width, a.height, pair.scale);
    CHECK(std::isfinite(gpu_value));
    CHECK(gpu_value == Approx(cpu).margin(kTolerance));
    if (a.pixels == b.pixels) CHECK(gpu_value == 1.0);
  }
  std::printf("max |GPU - CPU| = %.2e\n\n", worst);
  return worst;
}

}  // namespace

TEST_CASE("GPU SSIM equals the CPU path on image pairs from 1x1 to 4096x4096, OpenGL", "[gpu_ssim]") {
  std::printf("OpenGL 4.3+ core:\n");
  CHECK(check_pairs(GlApi::kDesktop, true) < kTolerance);
}

TEST_CASE("GPU SSIM equals the CPU path in OpenGL ES 3.1", "[gpu_ssim][es]") {
  std::printf("OpenGL ES 3.1+ (pairs up to a megapixel):\n");
  CHECK(check_pairs(GlApi::kEs, false) < kTolerance);
}

TEST_CASE("flat regions far from the mean keep their precision in float", "[gpu_ssim]") {
  // docs/ssim.md: float moments about zero were 3e-5 off here; the shaders' local origins are
  // not. Two flat halves at non-integer luma, a faint difference; float textures hold them exactly.
  GpuSsim& gpu = *gl(GlApi::kDesktop).gpu;
  for (const auto& [low, high] : {std::pair{0.1f, 250.7f}, {20.77f, 199.9f}, {5.3f, 254.9f}}) {
    const int width = 200, height = 100;
    std::vector<float> a(width * height * 4), b(a.size());
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const float value = (x < width / 2 ? low : high) / 255.0f;
        const float other = value + (0.37f + 0.25f * hash_noise(x, y, 17)) / 255.0f;
        for (int c = 0; c < 4; ++c) {
          a[(y * width + x) * 4 + c] = c < 3 ? value : 1.0f;
          b[(y * width + x) * 4 + c] = c < 3 ? other : 1.0f;
        }
      }
    const auto luma = [&](const std::vector<float>& rgba) {
      return glbudget::quality::luma_from_unit_float(rgba.data(), width, height, 4);
    };
    const double cpu = glbudget::quality::ssim(luma(a).view(), luma(b).view());
    GlTexture ta(&HeadlessGlContext::proc_address, width, height, GL_RGBA32F, GL_RGBA, GL_FLOAT, a.data());
    GlTexture tb(&HeadlessGlContext::proc_address, width, height, GL_RGBA32F, GL_RGBA, GL_FLOAT, b.data());
    CAPTURE(low, high, cpu);
    for (const int scale : {1, 2}) {
      CAPTURE(scale);
      const double expected = glbudget::quality::ssim(luma(a).view(), luma(b).view(), {scale, 0});
      CHECK(gpu.wait(gpu.submit(ta.name(), tb.name(), width, height, scale)) == Approx(expected).margin(1e-6));
    }
    CHECK(gpu.wait(gpu.submit(ta.name(), ta.name(), width, height, 1)) == 1.0);
  }
}

TEST_CASE("GPU SSIM reads sRGB and half-float textures by their values", "[gpu_ssim]") {
  GpuSsim& gpu = *gl(GlApi::kDesktop).gpu;
  const Rgba8 a = frame(320, 180), b = with_noise(frame(320, 180, 0.5f), 10.0f, 3);
  const double cpu = glbudget::quality::ssim(a.luma().view(), b.luma().view());
  // sRGB: the same code values, which texelFetch decodes to linear and the shader re-encodes.
  const auto srgb_a = upload(a, GL_SRGB8_ALPHA8), srgb_b = upload(b, GL_SRGB8_ALPHA8);
  CHECK(gpu.wait(gpu.submit(srgb_a->name(), srgb_b->name(), a.width, a.height, 1)) == Approx(cpu).margin(1e-6));
  // One sRGB, one linear texture with the same codes: the same values too.
  const auto linear_b = upload(b);
  CHECK(gpu.wait(gpu.submit(srgb_a->name(), linear_b->name(), a.width, a.height, 2)) ==
        Approx(glbudget::quality::ssim(a.luma().view(), b.luma().view(), {2, 0})).margin(1e-6));
  // RGBA16F: values k / 1024, exact in half precision, read as [0, 1] x 255.
  std::vector<float> fa(a.pixels.size()), fb(b.pixels.size());
  for (std::size_t i = 0; i < fa.size(); ++i) {
    fa[i] = std::round(a.pixels[i] * 1024.0f / 255.0f) / 1024.0f;
    fb[i] = std::round(b.pixels[i] * 1024.0f / 255.0f) / 1024.0f;
  }
  const auto luma_a = glbudget::quality::luma_from_unit_float(fa.data(), a.width, a.height, 4);
  const auto luma_b = glbudget::quality::luma_from_unit_float(fb.data(), a.width, a.height, 4);
  GlTexture half_a(&HeadlessGlContext::proc_address, a.width, a.height, GL_RGBA16F, GL_RGBA, GL_FLOAT, fa.data());
  GlTexture half_b(&HeadlessGlContext::proc_address, a.width, a.height, GL_RGBA16F, GL_RGBA, GL_FLOAT, fb.data());
  for (const int scale : {1, 4})
    CHECK(gpu.wait(gpu.submit(half_a.name(), half_b.name(), a.width, a.height, scale)) ==
          Approx(glbudget::quality::ssim(luma_a.view(), luma_b.view(), {scale, 0})).margin(1e-6));
}

TEST_CASE("GPU SSIM of a region of larger textures is the SSIM of that region", "[gpu_ssim]") {
  GpuSsim& gpu = *gl(GlApi::kDesktop).gpu;
  const Rgba8 a = frame(160, 120), b = with_noise(a, 20.0f, 9);
  const auto luma_a = a.luma(), luma_b = b.luma();
  const glbudget::quality::LumaView region_a{luma_a.pixels.data(), 101, 75, luma_a.width};
  const glbudget::quality::LumaView region_b{luma_b.pixels.data(), 101, 75, luma_b.width};
  const auto ta = upload(a), tb = upload(b);
  for (const int scale : {1, 2, 4})
    CHECK(gpu.wait(gpu.submit(ta->name(), tb->name(), 101, 75, scale)) ==
          Approx(glbudget::quality::ssim(region_a, region_b, {scale, 0})).margin(kTolerance));
}

TEST_CASE("GpuSsim leaves the GL state it touches as it found it", "[gpu_ssim][state]") {
  for (const GlApi api : {GlApi::kDesktop, GlApi::kEs}) {
    GpuSsim& gpu = *gl(api).gpu;
    const auto get_error = entry<PFNGLGETERRORPROC>("glGetError");
    const auto get_integer = entry<PFNGLGETINTEGERVPROC>("glGetIntegerv");
    const auto get_integer_i = entry<PFNGLGETINTEGERI_VPROC>("glGetIntegeri_v");
    const auto get_integer64_i = entry<PFNGLGETINTEGER64I_VPROC>("glGetInteger64i_v");
    const auto active_texture = entry<PFNGLACTIVETEXTUREPROC>("glActiveTexture");
    const auto bind_texture = entry<PFNGLBINDTEXTUREPROC>("glBindTexture");
    const auto bind_buffer = entry<PFNGLBINDBUFFERPROC>("glBindBuffer");
    const auto bind_buffer_range = entry<PFNGLBINDBUFFERRANGEPROC>("glBindBufferRange");
    const auto bind_buffer_base = entry<PFNGLBINDBUFFERBASEPROC>("glBindBufferBase");
    const auto buffer_data = entry<PFNGLBUFFERDATAPROC>("glBufferData");
    const auto gen_buffers = entry<PFNGLGENBUFFERSPROC>("glGenBuffers");
    const auto delete_buffers = entry<PFNGLDELETEBUFFERSPROC>("glDeleteBuffers");
    const auto gen_samplers = entry<PFNGLGENSAMPLERSPROC>("glGenSamplers");
    const auto delete_samplers = entry<PFNGLDELETESAMPLERSPROC>("glDeleteSamplers");
    const auto bind_sampler = entry<PFNGLBINDSAMPLERPROC>("glBindSampler");
    const auto use_program = entry<PFNGLUSEPROGRAMPROC>("glUseProgram");
    const auto create_shader_program = entry<PFNGLCREATESHADERPROGRAMVPROC>("glCreateShaderProgramv");
    const auto delete_program = entry<PFNGLDELETEPROGRAMPROC>("glDeleteProgram");

    const Rgba8 a = frame(96, 64), b = with_noise(a, 15.0f, 2);
    const auto ta = upload(a), tb = upload(b), other_texture = upload(frame(8, 8));
    const char* source = api == GlApi::kDesktop ? "#version 430 core\nlayout(local_size_x = 1) in;\nvoid main() {}\n"
                                                : "#version 310 es\nlayout(local_size_x = 1) in;\nvoid main() {}\n";
    const GLuint program = create_shader_program(GL_COMPUTE_SHADER, 1, &source);
    GLuint buffers[4], sampler = 0;
    gen_buffers(4, buffers);
    for (const GLuint buffer : buffers) {
      bind_buffer(GL_SHADER_STORAGE_BUFFER, buffer);
      buffer_data(GL_SHADER_STORAGE_BUFFER, 4096, nullptr, GL_STATIC_DRAW);
    }
    gen_samplers(1, &sampler);
    // The app's state: a program, textures on units 0 and 1, a sampler on unit 1, unit 3
    // active, a range, a whole buffer and nothing on SSBO bindings 0..2, generic bindings.
    use_program(program);
    active_texture(GL_TEXTURE0);
    bind_texture(GL_TEXTURE_2D, other_texture->name());
    active_texture(GL_TEXTURE1);
    bind_texture(GL_TEXTURE_2D, ta->name());
    bind_sampler(1, sampler);
    active_texture(GL_TEXTURE3);
    bind_buffer_range(GL_SHADER_STORAGE_BUFFER, 0, buffers[0], 256, 512);
    bind_buffer_base(GL_SHADER_STORAGE_BUFFER, 1, buffers[1]);
    bind_buffer_base(GL_SHADER_STORAGE_BUFFER, 2, 0);
    bind_buffer(GL_SHADER_STORAGE_BUFFER, buffers[2]);
    bind_buffer(GL_COPY_READ_BUFFER, buffers[3]);
    REQUIRE(get_error() == GL_NO_ERROR);

    for (const int scale : {1, 2}) {
      const std::uint64_t ticket = gpu.submit(ta->name(), tb->name(), a.width, a.height, scale);
      gpu.poll(ticket);
      const double value = gpu.wait(ticket);
      CHECK(value == Approx(glbudget::quality::ssim(a.luma().view(), b.luma().view(), {scale, 0})).margin(kTolerance));
    }

    CAPTURE(api == GlApi::kDesktop ? "OpenGL" : "OpenGL ES");
    CHECK(get_error() == GL_NO_ERROR);  // and none of ours was left for the app to find
    const auto integer = [&](GLenum name) {
      GLint value = -1;
      get_integer(name, &value);
      return value;
    };
    CHECK(integer(GL_CURRENT_PROGRAM) == static_cast<GLint>(program));
    CHECK(integer(GL_ACTIVE_TEXTURE) == GL_TEXTURE3);
    active_texture(GL_TEXTURE0);
    CHECK(integer(GL_TEXTURE_BINDING_2D) == static_cast<GLint>(other_texture->name()));
    CHECK(integer(GL_SAMPLER_BINDING) == 0);
    active_texture(GL_TEXTURE1);
    CHECK(integer(GL_TEXTURE_BINDING_2D) == static_cast<GLint>(ta->name()));
    CHECK(integer(GL_SAMPLER_BINDING) == static_cast<GLint>(sampler));
    const auto indexed = [&](GLenum name, GLuint index) {
      GLint value = -1;
      get_integer_i(name, index, &value);
      return value;
    };
    const auto indexed64 = [&](GLenum name, GLuint index) {
      GLint64 value = -1;
      get_integer64_i(name, index, &value);
      return value;
    };
    CHECK(indexed(GL_SHADER_STORAGE_BUFFER_BINDING, 0) == static_cast<GLint>(buffers[0]));
    CHECK(indexed64(GL_SHADER_STORAGE_BUFFER_START, 0) == 256);
    CHECK(indexed64(GL_SHADER_STORAGE_BUFFER_SIZE, 0) == 512);
    CHECK(indexed(GL_SHADER_STORAGE_BUFFER_BINDING, 1) == static_cast<GLint>(buffers[1]));
    CHECK(indexed64(GL_SHADER_STORAGE_BUFFER_SIZE, 1) == 0);
    CHECK(indexed(GL_SHADER_STORAGE_BUFFER_BINDING, 2) == 0);
    CHECK(integer(GL_SHADER_STORAGE_BUFFER_BINDING) == static_cast<GLint>(buffers[2]));
    CHECK(integer(GL_COPY_READ_BUFFER_BINDING) == static_cast<GLint>(buffers[3]));

    use_program(0);
    bind_sampler(1, 0);
    delete_samplers(1, &sampler);
    delete_buffers(4, buffers);
    delete_program(program);
    active_texture(GL_TEXTURE0);
  }
}

TEST_CASE("poll never blocks and wait returns what poll does", "[gpu_ssim]") {
  GpuSsim& gpu = *gl(GlApi::kDesktop).gpu;
  const Rgba8 a = frame(1920, 1080), b = with_noise(a, 12.0f, 4);
  const auto ta = upload(a), tb = upload(b);
  const std::uint64_t ticket = gpu.submit(ta->name(), tb->name(), a.width, a.height, 1);
  // Before the fence can have signalled on a GPU; on llvmpipe the dispatch ran in submit.
  const auto start = std::chrono::steady_clock::now();
  const std::optional<double> first = gpu.poll(ticket);
  const std::chrono::duration<double> polled = std::chrono::steady_clock::now() - start;
  CHECK(polled.count() < 0.05);
  std::optional<double> value = first;
  for (int i = 0; i < 10000 && !value; ++i) value = gpu.poll(ticket);
  const double waited = gpu.wait(ticket);
  if (value) CHECK(*value == waited);
  CHECK(gpu.poll(ticket) == waited);  // kept until kTicketsKept later submits
  CHECK(waited == Approx(glbudget::quality::ssim(a.luma().view(), b.luma().view())).margin(kTolerance));
}

TEST_CASE("tickets are kept for kTicketsKept submits, in flight together", "[gpu_ssim]") {
  GpuSsim& gpu = *gl(GlApi::kDesktop).gpu;
  std::vector<std::unique_ptr<GlTexture>> textures;
  std::vector<std::uint64_t> tickets;
  std::vector<double> expected;
  for (int i = 0; i <= GpuSsim::kTicketsKept; ++i) {
    const Rgba8 a = frame(40 + i, 30), b = with_noise(a, 2.0f * i, 5);
    textures.push_back(upload(a));
    textures.push_back(upload(b));
    tickets.push_back(gpu.submit(textures[textures.size() - 2]->name(), textures.back()->name(), a.width, a.height, 1));
    expected.push_back(glbudget::quality::ssim(a.luma().view(), b.luma().view()));
  }
  CHECK_THROWS_AS(gpu.poll(tickets.front()), std::out_of_range);
  CHECK_THROWS_AS(gpu.wait(tickets.front()), std::out_of_range);
  for (std::size_t i = tickets.size(); i-- > 1;) CHECK(gpu.wait(tickets[i]) == Approx(expected[i]).margin(kTolerance));
  CHECK_THROWS_AS(gpu.poll(0), std::out_of_range);
  CHECK_THROWS_AS(gpu.poll(tickets.back() + 1), std::out_of_range);
}

TEST_CASE("submit refuses what it cannot compare", "[gpu_ssim]") {
  GpuSsim& gpu = *gl(GlApi::kDesktop).gpu;
  const auto t = upload(frame(32, 16));
  CHECK_THROWS_AS(gpu.submit(t->name(), t->name(), 32, 16, 3), std::invalid_argument);
  CHECK_THROWS_AS(gpu.submit(t->name(), t->name(), 0, 16, 1), std::invalid_argument);
  CHECK_THROWS_AS(gpu.submit(t->name(), t->name(), 33, 16, 1), std::invalid_argument);  // larger than the texture
  CHECK_THROWS_AS(gpu.submit(t->name(), 987654, 32, 16, 1), std::invalid_argument);
  CHECK(entry<PFNGLGETERRORPROC>("glGetError")() == GL_NO_ERROR);
}

namespace {

// A loader that reports another version or hides an entry point, around the real one.
const char* g_fake_version = nullptr;
const char* g_hidden = nullptr;

const GLubyte* APIENTRY fake_get_string(GLenum name) {
  static const auto real = reinterpret_cast<PFNGLGETSTRINGPROC>(HeadlessGlContext::proc_address("glGetString"));
  return name == GL_VERSION && g_fake_version ? reinterpret_cast<const GLubyte*>(g_fake_version) : real(name);
}

void* fake_loader(const char* name) {
  if (g_hidden && std::strcmp(name, g_hidden) == 0) return nullptr;
  if (std::strcmp(name, "glGetString") == 0) return reinterpret_cast<void*>(&fake_get_string);
  return HeadlessGlContext::proc_address(name);
}

std::unique_ptr<GpuSsim> create_with(const char* version, const char* hidden, std::string& why_not) {
  g_fake_version = version;
  g_hidden = hidden;
  auto gpu = GpuSsim::create(&fake_loader, &why_not);
  g_fake_version = g_hidden = nullptr;
  return gpu;
}

}  // namespace

TEST_CASE("create says why a context cannot run it, and takes every path it can", "[gpu_ssim]") {
  gl(GlApi::kDesktop);
  std::string why;
  CHECK_FALSE(create_with("4.1 (Core Profile) Fake", nullptr, why));
  CHECK_THAT(why, Catch::Contains("compute shaders need OpenGL 4.3"));
  CHECK_FALSE(create_with("3.3 (Compatibility Profile) Fake", nullptr, why));
  CHECK_THAT(why, Catch::Contains("3.3 (Compatibility Profile) Fake"));
  CHECK_FALSE(create_with(nullptr, "glDispatchCompute", why));
  CHECK_THAT(why, Catch::Contains("glDispatchCompute"));
  CHECK_FALSE(GpuSsim::create(nullptr, &why));

  // OpenGL 4.2 with ARB_compute_shader and ARB_shader_storage_buffer_object (llvmpipe has
  // both): the GLSL 4.20 shaders, same results.
  const Rgba8 a = frame(200, 120), b = with_noise(a, 12.0f, 6);
  const double cpu = glbudget::quality::ssim(a.luma().view(), b.luma().view(), {2, 0});
  auto gpu420 = create_with("4.2 (Core Profile) Fake", nullptr, why);
  INFO(why);
  REQUIRE(gpu420);
  CHECK(gpu_ssim(*gpu420, a, b, 2) == Approx(cpu).margin(kTolerance));
  CHECK(gpu_ssim(*gpu420, a, a, 1) == 1.0);
  gpu420.reset();

  // OpenGL ES 3.0 refused; ES 3.1 without 3.2's 'precise' takes it from OES_gpu_shader5.
  gl(GlApi::kEs);
  CHECK_FALSE(create_with("OpenGL ES 3.0 Fake", nullptr, why));
  CHECK_THAT(why, Catch::Contains("OpenGL ES 3.1"));
  auto gpu310 = create_with("OpenGL ES 3.1 Fake", nullptr, why);
  INFO(why);
  REQUIRE(gpu310);
  CHECK(gpu_ssim(*gpu310, a, b, 2) == Approx(cpu).margin(kTolerance));
  CHECK(gpu_ssim(*gpu310, a, a, 1) == 1.0);
}
