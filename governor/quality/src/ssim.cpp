#include "glbudget/quality/ssim.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "glbudget/quality/downscale.hpp"
#include "parallel_bands.hpp"
#include "ssim_kernels.hpp"
#include "ssim_validate.hpp"
#include "ssim_window.hpp"

namespace glbudget::quality {

namespace {

// Less work than this per band (about half a millisecond) and starting a thread does not pay;
// a band also re-filters the 10 rows above it.
constexpr int kMinBandPixels = 1 << 16;

double ssim_full_resolution(const LumaView& a, const LumaView& b, unsigned threads) {
  // Below the window the borders matter and the map is tiny: the reference computes it.
  if (!window_fits(a.width, a.height)) return ssim_reference(a, b, 1);
  const int map_width = a.width - 2 * kRadius, map_height = a.height - 2 * kRadius;
  std::vector<double> row_sums(static_cast<std::size_t>(map_height));
  run_in_bands(map_height, threads, std::max(2 * kWindow, kMinBandPixels / map_width),
               [&](int first, int end) { ssim_row_sums(a, b, first, end, row_sums.data()); });
  // Summed in row order whatever the bands were: the same result on any thread count.
  double total = 0.0;
  for (const double sum : row_sums) total += sum;
  return total / (static_cast<double>(map_width) * map_height);
}

}  // namespace

bool is_valid_scale(int scale) { return scale == 1 || scale == 2 || scale == 4; }

void validate_ssim_arguments(const LumaView& a, const LumaView& b, int scale) {
  if (!is_valid_scale(scale)) throw std::invalid_argument("the scale must be 1, 2 or 4, not " + std::to_string(scale));
  if (a.width <= 0 || a.height <= 0 || b.width <= 0 || b.height <= 0)
    throw std::invalid_argument("SSIM of an empty image");
  if (a.width != b.width || a.height != b.height)
    throw std::invalid_argument("SSIM of images of different sizes: " + std::to_string(a.width) + "x" +
                                std::to_string(a.height) + " and " + std::to_string(b.width) + "x" +
                                std::to_string(b.height));
}

double ssim(const LumaView& a, const LumaView& b, const SsimOptions& options) {
  validate_ssim_arguments(a, b, options.scale);
  if (options.scale == 1) return ssim_full_resolution(a, b, options.threads);
  const LumaImage small_a = box_downscale(a, options.scale, options.threads);
  const LumaImage small_b = box_downscale(b, options.scale, options.threads);
  return ssim_full_resolution(small_a.view(), small_b.view(), options.threads);
}

int wang_rule_scale(int width, int height) {
  const long factor = std::max(1L, std::lround(std::min(width, height) / 256.0));
  return factor <= 1 ? 1 : factor <= 3 ? 2 : 4;
}

}  // namespace glbudget::quality
