// Image pairs for the GPU SSIM test: RGBA8 pixels (rows packed, row 0 first, as uploaded),
// rendered-like colour frames and the changes a cheaper configuration makes to them, noise,
// gradients, constants. Deterministic on every platform (no std distributions).
#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "glbudget/quality/luma_image.hpp"

namespace gpu_ssim_test {

struct Rgba8 {
  int width = 0, height = 0;
  std::vector<std::uint8_t> pixels;  // RGBA

  Rgba8(int width, int height)
      : width(width), height(height), pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4) {}
  std::uint8_t* at(int x, int y) { return &pixels[(static_cast<std::size_t>(y) * width + x) * 4]; }
  const std::uint8_t* at(int x, int y) const { return &pixels[(static_cast<std::size_t>(y) * width + x) * 4]; }
  glbudget::quality::LumaImage luma() const {
    return glbudget::quality::luma_from_8bit(pixels.data(), width, height, 4);
  }
};

inline float hash_noise(std::uint32_t x, std::uint32_t y, std::uint32_t seed) {  // uniform in [-1, 1)
  std::uint32_t h = x * 0x8da6b343u ^ y * 0xd8163841u ^ seed * 0xcb1ab31fu;
  h ^= h >> 15;
  h *= 0x2c1b3c6du;
  h ^= h >> 12;
  h *= 0x297a2d39u;
  h ^= h >> 15;
  return static_cast<float>(h >> 8) / 8388608.0f - 1.0f;
}

inline std::uint8_t to_byte(float value) { return static_cast<std::uint8_t>(std::clamp(std::lround(value), 0L, 255L)); }

// A rendered-like frame at (u, v) in [0, 1]^2: a sky gradient, a checkered floor in perspective
// (aliasing towards the horizon), two lit spheres with hard silhouettes. RGB in [0, 255].
inline void scene(float u, float v, float aspect, float rgb[3]) {
  constexpr float horizon = 0.42f;
  if (v < horizon) {
    const float t = 1.0f - v / horizon;
    rgb[0] = 90.0f + 70.0f * t, rgb[1] = 140.0f + 60.0f * t, rgb[2] = 230.0f;
  } else {
    const float depth = 0.25f / (v - horizon + 1e-3f);
    const float tu = (u - 0.5f) * aspect * depth * 6.0f, tv = depth * 6.0f;
    const bool dark = (static_cast<int>(std::floor(tu)) + static_cast<int>(std::floor(tv))) & 1;
    const float fog = std::min(1.0f, depth / 12.0f);
    const float floor[3] = {dark ? 60.0f : 170.0f, dark ? 50.0f : 150.0f, dark ? 40.0f : 120.0f};
    for (int c = 0; c < 3; ++c) rgb[c] = floor[c] * (1.0f - fog) + 175.0f * fog;
  }
  const float spheres[2][6] = {{0.3f, 0.6f, 0.14f, 1.0f, 0.3f, 0.2f}, {0.65f, 0.55f, 0.1f, 0.3f, 0.9f, 0.4f}};
  for (const auto& s : spheres) {
    const float dx = (u - s[0]) * aspect / s[2], dy = (v - s[1]) / s[2];
    const float r2 = dx * dx + dy * dy;
    if (r2 >= 1.0f) continue;
    const float nz = std::sqrt(1.0f - r2);
    const float lambert = std::max(0.0f, -0.5f * dx - 0.6f * dy + 0.62f * nz);
    const float specular = std::pow(std::max(0.0f, -0.3f * dx - 0.4f * dy + 0.87f * nz), 40.0f);
    for (int c = 0; c < 3; ++c) rgb[c] = 15.0f + 200.0f * lambert * s[3 + c] + 150.0f * specular;
  }
}

// shift: the camera moved by this many pixels to the right.
inline Rgba8 frame(int width, int height, float shift = 0.0f) {
  Rgba8 image(width, height);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      float rgb[3];
      scene((static_cast<float>(x) + 0.5f + shift) / static_cast<float>(width),
            (static_cast<float>(y) + 0.5f) / static_cast<float>(height), aspect, rgb);
      std::uint8_t* p = image.at(x, y);
      for (int c = 0; c < 3; ++c) p[c] = to_byte(rgb[c]);
      p[3] = 255;
    }
  return image;
}

// Per-channel noise of +-amplitude, clamped.
inline Rgba8 with_noise(Rgba8 image, float amplitude, std::uint32_t seed) {
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c) {
        std::uint8_t& value = image.at(x, y)[c];
        value = to_byte(
            value + amplitude * hash_noise(static_cast<std::uint32_t>(x * 3 + c), static_cast<std::uint32_t>(y), seed));
      }
  return image;
}

// The render-scale knob: the frame rendered at 1/factor of the size, upscaled bilinearly.
inline Rgba8 render_scaled(int width, int height, int factor) {
  const Rgba8 low = frame(width / factor, height / factor);
  Rgba8 image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float sx = std::clamp((x + 0.5f) / factor - 0.5f, 0.0f, low.width - 1.0f);
      const float sy = std::clamp((y + 0.5f) / factor - 0.5f, 0.0f, low.height - 1.0f);
      const int x0 = static_cast<int>(sx), y0 = static_cast<int>(sy);
      const int x1 = std::min(x0 + 1, low.width - 1), y1 = std::min(y0 + 1, low.height - 1);
      const float fx = sx - x0, fy = sy - y0;
      for (int c = 0; c < 4; ++c) {
        const float top = low.at(x0, y0)[c] * (1 - fx) + low.at(x1, y0)[c] * fx;
        const float bottom = low.at(x0, y1)[c] * (1 - fx) + low.at(x1, y1)[c] * fx;
        image.at(x, y)[c] = to_byte(top * (1 - fy) + bottom * fy);
      }
    }
  return image;
}

inline Rgba8 blur3(const Rgba8& in) {  // a 3x3 box, as cheaper antialiasing softens
  Rgba8 out(in.width, in.height);
  for (int y = 0; y < in.height; ++y)
    for (int x = 0; x < in.width; ++x)
      for (int c = 0; c < 4; ++c) {
        float sum = 0.0f;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            sum += in.at(std::clamp(x + dx, 0, in.width - 1), std::clamp(y + dy, 0, in.height - 1))[c];
        out.at(x, y)[c] = to_byte(sum / 9.0f);
      }
  return out;
}

inline Rgba8 banded(Rgba8 image, int levels) {  // as from a cheaper shading level
  const float step = 255.0f / static_cast<float>(levels - 1);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    if (i % 4 != 3) image.pixels[i] = to_byte(std::round(image.pixels[i] / step) * step);
  return image;
}

inline Rgba8 noise(int width, int height, std::uint32_t seed) {  // uniform 0..255 per channel
  Rgba8 image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      for (int c = 0; c < 4; ++c)
        image.at(x, y)[c] = to_byte(
            127.5f + 127.5f * hash_noise(static_cast<std::uint32_t>(x * 4 + c), static_cast<std::uint32_t>(y), seed));
  return image;
}

inline Rgba8 constant(int width, int height, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  Rgba8 image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      std::uint8_t* p = image.at(x, y);
      p[0] = r, p[1] = g, p[2] = b, p[3] = 255;
    }
  return image;
}

// A colour ramp along x (horizontal) or y.
inline Rgba8 gradient(int width, int height, bool horizontal) {
  Rgba8 image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const float t = horizontal ? static_cast<float>(x) / static_cast<float>(width - 1)
                                 : static_cast<float>(y) / static_cast<float>(height - 1);
      std::uint8_t* p = image.at(x, y);
      p[0] = to_byte(255.0f * t), p[1] = to_byte(200.0f - 150.0f * t), p[2] = to_byte(30.0f + 60.0f * t), p[3] = 255;
    }
  return image;
}

// Black and white squares of `size` pixels, offset by `shift`: flat windows far from any mean.
inline Rgba8 checkerboard(int width, int height, int size, int shift) {
  Rgba8 image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const std::uint8_t value = (((x + shift) / size + y / size) & 1) ? 255 : 0;
      std::uint8_t* p = image.at(x, y);
      p[0] = p[1] = p[2] = value, p[3] = 255;
    }
  return image;
}

}  // namespace gpu_ssim_test
