#pragma once
// Luma images, what SSIM is computed on: one float per pixel on the 8-bit scale [0, 255],
// not rounded. Luma is Rec. 709's weighted sum of the gamma-encoded (sRGB) code values, the
// weights of sRGB's own primaries (and of skimage.color.rgb2gray).
#include <cstddef>
#include <cstdint>
#include <vector>

namespace glbudget::quality {

inline constexpr double kLumaRed = 0.2126;
inline constexpr double kLumaGreen = 0.7152;
inline constexpr double kLumaBlue = 0.0722;
// SSIM's dynamic range L: C1 = (K1 L)^2 and C2 = (K2 L)^2.
inline constexpr double kDataRange = 255.0;

// A read-only window on luma pixels owned elsewhere.
struct LumaView {
  const float* pixels = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  // floats from the start of one row to the next

  const float* row(int y) const { return pixels + static_cast<std::ptrdiff_t>(y) * stride; }
};

struct LumaImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // packed rows

  LumaImage() = default;
  LumaImage(int width, int height);
  float* row(int y) { return pixels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width); }
  const float* row(int y) const {
    return pixels.data() + static_cast<std::size_t>(y) * static_cast<std::size_t>(width);
  }
  LumaView view() const { return {pixels.data(), width, height, width}; }
};

// Interleaved pixels, rows packed: channels 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA).
// Grey is taken as luma; alpha is ignored. Throws std::invalid_argument for other counts.
LumaImage luma_from_8bit(const std::uint8_t* pixels, int width, int height, int channels);
// The same from values in [0, 1] (16-bit or float images), scaled to [0, 255].
LumaImage luma_from_unit_float(const float* pixels, int width, int height, int channels);

}  // namespace glbudget::quality
