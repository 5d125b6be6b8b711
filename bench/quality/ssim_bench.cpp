// CPU SSIM throughput in Mpix/s (pixels of the input images per second, box-averaging included):
// the SIMD path over all threads and on one thread against the scalar double-precision
// reference, all timed in this run, at 640x360, 1920x1080 and 3840x2160 and scales 1, 2, 4.
// The goal is >= 120 Mpix/s at full resolution on this 2-core machine; rmgr/ssim
// reports 57 Mpix/s on one AVX2+FMA core. Then one thread per SIMD target, and what the scale
// knob costs: SSIM at scale 2 and 4 minus SSIM at full resolution on rendered-like frames.
//
// ssim_bench [--seconds S] [--rounds N]: each figure is the best call of N rounds (default 3)
// that each spend at least S seconds (default 0.5) and 3 calls on it.
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "glbudget/quality/downscale.hpp"
#include "glbudget/quality/simd_target.hpp"
#include "glbudget/quality/ssim.hpp"

using namespace glbudget::quality;

namespace {

double g_seconds = 0.5;
int g_rounds = 3;
volatile double g_sink = 0.0;

// Seconds per call of f: the best of at least 3 calls and g_seconds in all.
double best_of(const std::function<double()>& f) {
  double best = INFINITY, spent = 0.0;
  for (int calls = 0; calls < 3 || spent < g_seconds; ++calls) {
    const auto start = std::chrono::steady_clock::now();
    g_sink = g_sink + f();
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    best = std::min(best, elapsed.count());
    spent += elapsed.count();
  }
  return best;
}

// best_of for each call, over g_rounds rounds that go through all of them in turn: a burst of
// other work on a shared machine then spoils one round of a figure, not the figure.
std::vector<double> best_seconds(const std::vector<std::function<double()>>& calls) {
  std::vector<double> best(calls.size(), INFINITY);
  for (int round = 0; round < g_rounds; ++round)
    for (std::size_t i = 0; i < calls.size(); ++i) best[i] = std::min(best[i], best_of(calls[i]));
  return best;
}

float hash_noise(std::uint32_t x, std::uint32_t y, std::uint32_t seed) {  // uniform in [-1, 1)
  std::uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  return static_cast<float>(h >> 8) / 8388608.0f - 1.0f;
}

// A rendered-like frame, evaluated at (u, v) in [0, 1]^2: a sky gradient, a checkered floor in
// perspective (aliasing towards the horizon), and three lit spheres with hard silhouettes.
float scene(float u, float v, float aspect) {
  constexpr float horizon = 0.42f;
  float value = 0.0f;
  if (v < horizon) {
    value = 150.0f + 80.0f * (1.0f - v / horizon);
  } else {
    const float depth = 0.25f / (v - horizon + 1e-3f);
    const float tu = (u - 0.5f) * aspect * depth * 6.0f, tv = depth * 6.0f;
    const bool dark = (static_cast<int>(std::floor(tu)) + static_cast<int>(std::floor(tv))) & 1;
    const float fog = std::min(1.0f, depth / 12.0f);
    value = (dark ? 55.0f : 160.0f) * (1.0f - fog) + 170.0f * fog;
  }
  const float spheres[3][3] = {{0.3f, 0.6f, 0.14f}, {0.62f, 0.55f, 0.1f}, {0.8f, 0.75f, 0.07f}};
  for (const auto& s : spheres) {
    const float dx = (u - s[0]) * aspect / s[2], dy = (v - s[1]) / s[2];
    const float r2 = dx * dx + dy * dy;
    if (r2 >= 1.0f) continue;
    const float nz = std::sqrt(1.0f - r2);
    const float lambert = std::max(0.0f, -0.5f * dx - 0.6f * dy + 0.62f * nz);
    const float specular = std::pow(std::max(0.0f, -0.3f * dx - 0.4f * dy + 0.87f * nz), 40.0f);
    value = std::min(255.0f, 20.0f + 180.0f * lambert + 120.0f * specular);
  }
  return value;
}

LumaImage render(int width, int height, float shift_pixels = 0.0f) {
  LumaImage image(width, height);
  const float aspect = static_cast<float>(width) / height;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      image.row(y)[x] = scene((x + 0.5f + shift_pixels) / width, (y + 0.5f) / height, aspect);
  return image;
}

LumaImage add_noise(LumaImage image, float amplitude, std::uint32_t seed) {
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      float& value = image.row(y)[x];
      value = std::clamp(value + amplitude * hash_noise(x, y, seed), 0.0f, 255.0f);
    }
  return image;
}

// The render-scale knob: the frame rendered at 1/factor resolution, bilinearly upscaled.
LumaImage render_scaled(int width, int height, int factor) {
  const LumaImage low = render(width / factor, height / factor);
  LumaImage image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float sx = std::clamp((x + 0.5f) / factor - 0.5f, 0.0f, low.width - 1.0f);
      const float sy = std::clamp((y + 0.5f) / factor - 0.5f, 0.0f, low.height - 1.0f);
      const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);
      const int x1 = std::min(x0 + 1, low.width - 1), y1 = std::min(y0 + 1, low.height - 1);
      const float fx = sx - x0, fy = sy - y0;
      const float top = low.row(y0)[x0] * (1 - fx) + low.row(y0)[x1] * fx;
      const float bottom = low.row(y1)[x0] * (1 - fx) + low.row(y1)[x1] * fx;
      image.row(y)[x] = top * (1 - fy) + bottom * fy;
    }
  return image;
}

LumaImage blur3(const LumaImage& in) {  // a 3x3 box, as a cheap antialiasing filter would soften
  LumaImage out(in.width, in.height);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x) {
      float sum = 0.0f;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          sum += in.row(std::clamp(y + dy, 0, in.height - 1))[std::clamp(x + dx, 0, in.width - 1)];
      out.row(y)[x] = sum / 9.0f;
    }
  return out;
}

LumaImage quantise(LumaImage image, float step) {  // banding, as from a cheaper shading level
  for (float& value : image.pixels) value = std::round(value / step) * step;
  return image;
}

void throughput_table(unsigned threads) {
  std::printf("CPU SSIM throughput, Mpix/s of input pixels (best of %d rounds of >= %.2f s and >= 3 calls)\n", g_rounds,
              g_seconds);
  std::printf("SIMD target %s, %u threads; frame vs the same frame with +-12 noise\n\n", simd_target().c_str(),
              threads);
  const int sizes[][2] = {{640, 360}, {1920, 1080}, {3840, 2160}};
  const int scales[] = {1, 2, 4};
  std::vector<std::pair<LumaImage, LumaImage>> images;
  for (const auto& size : sizes) {
    LumaImage a = render(size[0], size[1]);
    LumaImage b = add_noise(a, 12.0f, 1);
    images.emplace_back(std::move(a), std::move(b));
  }
  std::vector<std::function<double()>> calls;  // per size and scale: reference, one thread, all
  for (const auto& [a, b] : images)
    for (const int scale : scales) {
      calls.push_back([&, scale] { return ssim_reference(a.view(), b.view(), scale); });
      calls.push_back([&, scale] { return ssim(a.view(), b.view(), {scale, 1}); });
      calls.push_back([&, scale] { return ssim(a.view(), b.view(), {scale, threads}); });
    }
  const std::vector<double> seconds = best_seconds(calls);
  std::printf("%-10s %5s %10s %10s %10s %9s %9s %12s %10s\n", "size", "scale", "reference", "SIMD 1thr", "SIMD all",
              "x ref 1t", "x ref all", "SSIM", "|diff|");
  std::size_t cell = 0;
  for (std::size_t s = 0; s < images.size(); ++s) {
    const auto& [a, b] = images[s];
    const double mpix = static_cast<double>(a.width) * a.height / 1e6;
    for (const int scale : scales) {
      const double reference = ssim_reference(a.view(), b.view(), scale);
      const double fast = ssim(a.view(), b.view(), {scale, threads});
      const double t_ref = seconds[cell], t_one = seconds[cell + 1], t_all = seconds[cell + 2];
      cell += 3;
      std::printf("%4dx%-5d %5d %10.1f %10.1f %10.1f %9.1f %9.1f %12.8f %10.1e\n", a.width, a.height, scale,
                  mpix / t_ref, mpix / t_one, mpix / t_all, t_ref / t_one, t_ref / t_all, fast,
                  std::abs(fast - reference));
    }
  }
}

void target_table() {
  const LumaImage a = render(1920, 1080), b = add_noise(a, 12.0f, 1);
  const double mpix = 1920.0 * 1080.0 / 1e6;
  const std::vector<std::string> targets = simd_targets();
  std::vector<std::function<double()>> calls = {[&] { return ssim_reference(a.view(), b.view(), 1); }};
  for (const std::string& target : targets)
    calls.push_back([&] {
      pin_simd_target(target);
      const double value = ssim(a.view(), b.view(), {1, 1});
      pin_simd_target("");
      return value;
    });
  const std::vector<double> seconds = best_seconds(calls);
  std::printf("\nOne thread per SIMD target, 1920x1080, scale 1 (the reference: %.1f Mpix/s)\n\n", mpix / seconds[0]);
  std::printf("%-8s %10s %9s\n", "target", "Mpix/s", "x ref");
  for (std::size_t i = 0; i < targets.size(); ++i)
    std::printf("%-8s %10.1f %9.1f\n", targets[i].c_str(), mpix / seconds[i + 1], seconds[0] / seconds[i + 1]);
}

void scale_trade_table(unsigned threads) {
  const int width = 1920, height = 1080;
  const LumaImage frame = render(width, height);
  struct Pair {
    const char* name;
    LumaImage other;
  };
  const Pair pairs[] = {
      {"render scale 1/2, bilinear", render_scaled(width, height, 2)},
      {"render scale 1/4, bilinear", render_scaled(width, height, 4)},
      {"3x3 blur", blur3(frame)},
      {"noise +-8", add_noise(frame, 8.0f, 2)},
      {"noise +-32", add_noise(frame, 32.0f, 3)},
      {"banding, 16 levels", quantise(frame, 16.0f)},
      {"camera moved 1 px", render(width, height, 1.0f)},
  };
  std::printf(
      "\nThe scale knob on rendered-like 1920x1080 frames: SSIM at full resolution, and the\n"
      "difference at scale 2 and 4 (SSIM(s) - SSIM(1)); time per comparison, %u threads\n\n",
      threads);
  std::printf("%-28s %10s %10s %10s\n", "frame vs", "SSIM(1)", "s=2 diff", "s=4 diff");
  for (const Pair& pair : pairs) {
    const double full = ssim(frame.view(), pair.other.view(), {1, threads});
    const double half = ssim(frame.view(), pair.other.view(), {2, threads});
    const double quarter = ssim(frame.view(), pair.other.view(), {4, threads});
    std::printf("%-28s %10.5f %+10.5f %+10.5f\n", pair.name, full, half - full, quarter - full);
  }
  std::vector<std::function<double()>> calls;
  for (const int scale : {1, 2, 4})
    calls.push_back([&, scale] { return ssim(frame.view(), pairs[0].other.view(), {scale, threads}); });
  const std::vector<double> seconds = best_seconds(calls);
  std::printf("%-28s %10.2f %10.2f %10.2f\n", "time per comparison, ms", 1e3 * seconds[0], 1e3 * seconds[1],
              1e3 * seconds[2]);
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--seconds") == 0 && i + 1 < argc) {
      g_seconds = std::atof(argv[++i]);
    } else if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) {
      g_rounds = std::max(1, std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr, "usage: ssim_bench [--seconds S] [--rounds N]\n");
      return 2;
    }
  }
  // A long-running process's steady state: freed images stay in the heap for the next call.
  // Otherwise glibc maps every buffer above its mmap threshold afresh, and the reference's
  // full-image planes measure this VM's page faults (4 to 37 Mpix/s for the same call).
  mallopt(M_MMAP_MAX, 0);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  const unsigned threads = std::max(1u, std::thread::hardware_concurrency());
  throughput_table(threads);
  target_table();
  scale_trade_table(threads);
  return 0;
}
