// GPU SSIM throughput (interpose/quality's compute shaders, GpuSsim) beside the CPU path in the
// same process, in Mpix/s of input pixels, at 640x360, 1920x1080 and 3840x2160 and scales 1, 2,
// 4: a rendered-like RGBA8 frame against itself with +-12 noise. In an EGL surfaceless context;
// on a machine without a GPU that is llvmpipe, where the "GPU" is the CPU (its compute
// dispatches run on LP_NUM_THREADS threads, one per core by default, before submit returns).
//
//   GPU        submit() + wait(): luma from the two textures, box average, SSIM, reduction
//   submit     the part of that spent in submit(), which on a real GPU only queues the work
//   CPU        glbudget::quality::ssim on luma images, on all cores
//   CPU+luma   the same from the RGBA8 pixels (luma_from_8bit first), what the GPU path does
//
// gpu_ssim_bench [--seconds S] [--rounds N]: each figure is the best call of N rounds (default 3)
// that each spend at least S seconds (default 0.5) and 3 calls on it.
#include <GL/glcorearb.h>
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <thread>
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

namespace {

double g_seconds = 0.5;
int g_rounds = 3;
volatile double g_sink = 0.0;

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// Seconds per call of f: the best of at least 3 calls and g_seconds in all.
double best_of(const std::function<double()>& f) {
  double best = INFINITY, spent = 0.0;
  for (int calls = 0; calls < 3 || spent < g_seconds; ++calls) {
    const auto start = Clock::now();
    g_sink = g_sink + f();
    const double elapsed = seconds_since(start);
    best = std::min(best, elapsed);
    spent += elapsed;
  }
  return best;
}

// best_of for each call over g_rounds rounds that go through all of them in turn: a burst of
// other work on a shared machine then spoils one round of a figure, not the figure.
std::vector<double> best_seconds(const std::vector<std::function<double()>>& calls) {
  std::vector<double> best(calls.size(), INFINITY);
  for (int round = 0; round < g_rounds; ++round)
    for (std::size_t i = 0; i < calls.size(); ++i) best[i] = std::min(best[i], best_of(calls[i]));
  return best;
}

std::string renderer() {
  const auto get_string = reinterpret_cast<PFNGLGETSTRINGPROC>(HeadlessGlContext::proc_address("glGetString"));
  const auto text = [&](GLenum name) {
    const GLubyte* value = get_string(name);
    return value ? std::string(reinterpret_cast<const char*>(value)) : std::string("?");
  };
  return text(GL_RENDERER) + ", " + text(GL_VERSION);
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
      g_seconds = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) {
      g_rounds = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: gpu_ssim_bench [--seconds S] [--rounds N]\n");
      return 2;
    }
  }
  // A long-running process's steady state, as ssim_bench: freed images stay in the heap.
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  std::string why_desktop, why_es;
  std::unique_ptr<HeadlessGlContext> context = HeadlessGlContext::open(GlApi::kDesktop, &why_desktop);
  if (!context) context = HeadlessGlContext::open(GlApi::kEs, &why_es);
  if (!context) {
    std::fprintf(stderr, "glbudget: no OpenGL context: %s; OpenGL ES: %s\n", why_desktop.c_str(), why_es.c_str());
    return 2;
  }
  std::string why_not;
  std::unique_ptr<GpuSsim> gpu = GpuSsim::create(&HeadlessGlContext::proc_address, &why_not);
  if (!gpu) {
    std::fprintf(stderr, "glbudget: no GPU SSIM: %s\n", why_not.c_str());
    return 2;
  }
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  std::printf("GPU SSIM throughput, Mpix/s of input pixels (best of %d rounds of >= %.2f s and >= 3 calls)\n", g_rounds,
              g_seconds);
  std::printf("GL: %s; CPU path on %u threads; frame vs the same frame with +-12 noise\n\n", renderer().c_str(),
              threads);
  std::printf("%-10s %5s %9s %9s %9s %9s %9s %9s %12s %10s\n", "size", "scale", "GPU", "GPU ms", "submit ms", "CPU",
              "CPU+luma", "GPU/CPU", "SSIM (GPU)", "|GPU-CPU|");
  const int sizes[][2] = {{640, 360}, {1920, 1080}, {3840, 2160}};
  for (const auto& size : sizes) {
    using namespace gpu_ssim_test;
    const Rgba8 a = frame(size[0], size[1]), b = with_noise(a, 12.0f, 1);
    const auto luma_a = a.luma(), luma_b = b.luma();
    const glbudget::GlProcLoader load = &HeadlessGlContext::proc_address;
    const GlTexture texture_a(load, a.width, a.height, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, a.pixels.data());
    const GlTexture texture_b(load, a.width, a.height, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, b.pixels.data());
    const double mpix = static_cast<double>(a.width) * a.height / 1e6;
    for (const int scale : {1, 2, 4}) {
      double submit_seconds = INFINITY;
      const auto on_gpu = [&] {
        const auto start = Clock::now();
        const std::uint64_t ticket = gpu->submit(texture_a.name(), texture_b.name(), a.width, a.height, scale);
        submit_seconds = std::min(submit_seconds, seconds_since(start));
        return gpu->wait(ticket);
      };
      const auto on_cpu = [&] { return glbudget::quality::ssim(luma_a.view(), luma_b.view(), {scale, threads}); };
      const auto on_cpu_from_rgba = [&] {
        return glbudget::quality::ssim(a.luma().view(), b.luma().view(), {scale, threads});
      };
      const std::vector<double> seconds = best_seconds({on_gpu, on_cpu, on_cpu_from_rgba});
      const double gpu_value = on_gpu(), cpu_value = on_cpu();
      std::printf("%4dx%-5d %5d %9.1f %9.2f %9.2f %9.1f %9.1f %9.2f %12.8f %10.1e\n", a.width, a.height, scale,
                  mpix / seconds[0], 1e3 * seconds[0], 1e3 * submit_seconds, mpix / seconds[1], mpix / seconds[2],
                  seconds[1] / seconds[0], gpu_value, std::abs(gpu_value - cpu_value));
    }
  }
  gpu.reset();  // its context still current
  return 0;
}
