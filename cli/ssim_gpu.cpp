#include "ssim_gpu.hpp"

#include <GL/glcorearb.h>

#include <memory>
#include <string>

#include "egl_context.hpp"
#include "gl_texture.hpp"
#include "gpu_ssim.hpp"

namespace glbudget::cli {

namespace {

std::unique_ptr<HeadlessGlContext> open_context() {
  std::string desktop_why, es_why;
  if (auto context = HeadlessGlContext::open(GlApi::kDesktop, &desktop_why)) return context;
  if (auto context = HeadlessGlContext::open(GlApi::kEs, &es_why)) return context;
  if (desktop_why == es_why) throw GpuUnavailable("no OpenGL context for --gpu: " + desktop_why);
  throw GpuUnavailable("no OpenGL context for --gpu: " + desktop_why + "; OpenGL ES 3.1: " + es_why);
}

// RGBA, as GL takes it: grey into all three colour channels, alpha opaque (SSIM ignores it).
template <typename T>
std::vector<T> to_rgba(const std::vector<T>& pixels, int channels, T opaque) {
  const std::size_t count = pixels.size() / static_cast<std::size_t>(channels);
  std::vector<T> rgba(count * 4);
  for (std::size_t i = 0; i < count; ++i) {
    const T* in = &pixels[i * static_cast<std::size_t>(channels)];
    T* out = &rgba[i * 4];
    out[0] = in[0];
    out[1] = channels >= 3 ? in[1] : in[0];
    out[2] = channels >= 3 ? in[2] : in[0];
    out[3] = opaque;
  }
  return rgba;
}

std::unique_ptr<GlTexture> upload(const DecodedImage& image) {
  const GlProcLoader load = &HeadlessGlContext::proc_address;
  if (image.floats.empty()) {
    const auto rgba = to_rgba<std::uint8_t>(image.bytes, image.channels, 255);
    return std::make_unique<GlTexture>(load, image.width, image.height, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE,
                                       rgba.data());
  }
  const auto rgba = to_rgba<float>(image.floats, image.channels, 1.0f);
  return std::make_unique<GlTexture>(load, image.width, image.height, GL_RGBA32F, GL_RGBA, GL_FLOAT, rgba.data());
}

}  // namespace

double ssim_on_gpu(const DecodedImage& a, const DecodedImage& b, int scale) {
  const std::unique_ptr<HeadlessGlContext> context = open_context();
  std::string why_not;
  const std::unique_ptr<GpuSsim> gpu = GpuSsim::create(&HeadlessGlContext::proc_address, &why_not);
  if (!gpu) throw GpuUnavailable("no GPU SSIM in this OpenGL context: " + why_not);
  const std::unique_ptr<GlTexture> texture_a = upload(a), texture_b = upload(b);
  return gpu->wait(gpu->submit(texture_a->name(), texture_b->name(), a.width, a.height, scale));
}

}  // namespace glbudget::cli
