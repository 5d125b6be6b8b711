#pragma once
// SSIM of two luma images (Wang, Bovik, Sheikh, Simoncelli 2004), e = 1 - SSIM. Exactly the
// mean skimage.metrics.structural_similarity(gaussian_weights=True, sigma=1.5,
// use_sample_covariance=False, data_range=255) returns, and defined for small images as well;
// the full definition (borders, small images, the scale knob) is in docs/ssim.md.
#include "glbudget/quality/luma_image.hpp"

namespace glbudget::quality {

inline constexpr double kSigma = 1.5;
// The Gaussian truncated at 3.5 sigma, radius int(3.5 * 1.5 + 0.5) as scipy rounds it: 11 taps.
inline constexpr int kRadius = 5;
inline constexpr int kWindow = 2 * kRadius + 1;
inline constexpr double kK1 = 0.01;
inline constexpr double kK2 = 0.03;

struct SsimOptions {
  int scale = 1;         // 1, 2 or 4: box-average scale x scale blocks first (downscale.hpp)
  unsigned threads = 0;  // row bands in parallel; 0: std::thread::hardware_concurrency()
};

// The SIMD (Highway, best target of this CPU) path over threads. Throws std::invalid_argument
// when the sizes differ, an image is empty or the scale is not 1, 2 or 4.
double ssim(const LumaView& a, const LumaView& b, const SsimOptions& options = {});

// The same definition computed plainly: scalar, double precision, one thread, the whole SSIM
// map with 'reflect' borders before the crop. The SIMD path and the GPU path are tested
// against it. Same exceptions as ssim().
double ssim_reference(const LumaView& a, const LumaView& b, int scale = 1);

bool is_valid_scale(int scale);

// Wang's rule (libvmaf, the SSIM authors' code): downsample by max(1, round(short side / 256)).
// Returns the knob value 1, 2 or 4 nearest that factor, the finer one on a tie.
int wang_rule_scale(int width, int height);

}  // namespace glbudget::quality
