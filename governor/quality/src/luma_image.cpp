#include "glbudget/quality/luma_image.hpp"

#include <stdexcept>
#include <string>

namespace glbudget::quality {

LumaImage::LumaImage(int width, int height)
    : width(width), height(height), pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height)) {}

namespace {

template <typename T>
LumaImage luma_from(const T* pixels, int width, int height, int channels, double unit) {
  if (channels < 1 || channels > 4)
    throw std::invalid_argument("luma needs 1 to 4 channels, not " + std::to_string(channels));
  if (width < 0 || height < 0) throw std::invalid_argument("negative image size");
  LumaImage luma(width, height);
  const std::size_t count = luma.pixels.size();
  for (std::size_t i = 0; i < count; ++i) {
    const T* pixel = pixels + i * static_cast<std::size_t>(channels);
    // In double, rounded to float once: within half a float ulp of the exact luma.
    const double value = channels < 3
                             ? static_cast<double>(pixel[0])
                             : kLumaRed * static_cast<double>(pixel[0]) + kLumaGreen * static_cast<double>(pixel[1]) +
                                   kLumaBlue * static_cast<double>(pixel[2]);
    luma.pixels[i] = static_cast<float>(value * unit);
  }
  return luma;
}

}  // namespace

LumaImage luma_from_8bit(const std::uint8_t* pixels, int width, int height, int channels) {
  return luma_from(pixels, width, height, channels, 1.0);
}

LumaImage luma_from_unit_float(const float* pixels, int width, int height, int channels) {
  return luma_from(pixels, width, height, channels, kDataRange);
}

}  // namespace glbudget::quality
