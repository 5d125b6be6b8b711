// `glbudget ssim --gpu`: the same SSIM computed by the shim's GPU path (GpuSsim) in a context
// of our own, to check it against the CPU path and time it.
#pragma once
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace glbudget::cli {

// Pixels as read from an image file: 8-bit values (bytes) or values in [0, 1] (floats, from
// 16-bit and float files), rows packed, the top row first.
struct DecodedImage {
  int width = 0, height = 0;
  int channels = 0;  // 1 (grey) or 3 (RGB)
  std::vector<std::uint8_t> bytes;
  std::vector<float> floats;
};

// No OpenGL context or no compute shaders here: what() says which.
struct GpuUnavailable : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// SSIM of two images of the same size on the GPU: an EGL surfaceless context (OpenGL 4.3 core,
// else OpenGL ES 3.1), the images as RGBA8 textures (RGBA32F for 16-bit and float images,
// grey in all three colour channels), GpuSsim. Throws GpuUnavailable, or std::exception for
// a failure on the way.
double ssim_on_gpu(const DecodedImage& a, const DecodedImage& b, int scale);

}  // namespace glbudget::cli
