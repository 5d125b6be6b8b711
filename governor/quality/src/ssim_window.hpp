#pragma once
// What the SIMD path and the reference share: the window weights, the constants and the crop.
#include <algorithm>
#include <array>
#include <cmath>

#include "glbudget/quality/ssim.hpp"

namespace glbudget::quality {

// scipy.ndimage's 1-D Gaussian: exp(-x^2 / (2 sigma^2)) for x in [-5, 5], normalised to sum 1.
inline std::array<double, kWindow> gaussian_window() {
  std::array<double, kWindow> weights{};
  double sum = 0.0;
  for (int k = 0; k < kWindow; ++k) {
    const double x = k - kRadius;
    weights[k] = std::exp(-0.5 / (kSigma * kSigma) * x * x);
    sum += weights[k];
  }
  for (double& weight : weights) weight /= sum;
  return weights;
}

inline constexpr double kC1 = (kK1 * kDataRange) * (kK1 * kDataRange);
inline constexpr double kC2 = (kK2 * kDataRange) * (kK2 * kDataRange);

// Map positions averaged along an axis of n pixels: skimage crops kRadius on each side; on an
// axis shorter than the window it crops only (n - 1) / 2, keeping the middle one or two.
inline int crop_margin(int n) { return std::min(kRadius, (n - 1) / 2); }

// The image is large enough for the SIMD path: every averaged window lies inside it.
inline bool window_fits(int width, int height) { return std::min(width, height) >= kWindow; }

}  // namespace glbudget::quality
