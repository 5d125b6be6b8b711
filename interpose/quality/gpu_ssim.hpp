// SSIM of two GL textures in compute shaders, for the quality probes (DESIGN.md, "Quality
// probes"): the definition of governor/quality's CPU path exactly (docs/ssim.md: Rec. 709 luma
// of the code values, 11x11 Gaussian window of sigma 1.5, 'reflect' borders, skimage's crop,
// the scale knob), laid out like fused-ssim, and read back behind a fence without waiting.
//
// It calls GL only through the loader it is given (inside the shim: the real driver, not the
// shim's hooks), in the context current when it was created, and leaves every piece of GL
// state it touches as it found it. Not thread-safe: one GpuSsim per context, used on the
// thread where that context is current.
#pragma once
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

namespace glbudget {

// A GL entry point by name ("glDispatchCompute"), e.g. eglGetProcAddress; null if unknown.
using GlProcLoader = void* (*)(const char* name);

class GpuSsim {
 public:
  // Tickets whose results are kept: a ticket is forgotten this many submits later. The probes
  // keep up to four frames in flight, each with up to eight comparisons (a sweep's seven
  // passes and the shown image against s0: apply/probes.cpp).
  static constexpr int kTicketsKept = 64;

  // For the context current now. Null, and why in *why_not, if it lacks compute shaders
  // (OpenGL < 4.3 without ARB_compute_shader, OpenGL ES < 3.1), an entry point is missing, or
  // a shader does not compile. Compiles its shaders now; buffers come with the first submit.
  static std::unique_ptr<GpuSsim> create(GlProcLoader load, std::string* why_not);
  // Releases its GL objects: its context must be current.
  ~GpuSsim();
  GpuSsim(const GpuSsim&) = delete;
  GpuSsim& operator=(const GpuSsim&) = delete;

  // Queues SSIM of texels [0, width) x [0, height) of level 0 of two GL_TEXTURE_2D textures
  // (GLuint names) and a fence, and returns at once with a ticket for poll()/wait(). Any colour
  // format sampled as vec4 (RGBA8, RGBA16F, SRGB8_ALPHA8 ...): luma is taken on the 8-bit
  // code-value scale (float formats times 255, sRGB formats re-encoded), alpha ignored; not
  // integer or depth formats. scale 1, 2 or 4: box-average scale x scale blocks first.
  // Throws std::invalid_argument for a bad size or scale, or a texture that is not one or is
  // smaller than width x height. (On llvmpipe the "GPU" is the CPU, and its dispatches run
  // before submit returns.)
  std::uint64_t submit(unsigned texture_a, unsigned texture_b, int width, int height, int scale);

  // Never blocks: the SSIM once the ticket's fence has signalled (it asks the driver to flush
  // the first time, so that it will), nullopt before. Throws std::out_of_range for a ticket
  // not among the last kTicketsKept submitted, std::runtime_error if the driver fails.
  std::optional<double> poll(std::uint64_t ticket);
  // Blocks until the SSIM is there (for the command and tests). Same exceptions as poll().
  double wait(std::uint64_t ticket);

 private:
  struct Impl;
  explicit GpuSsim(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace glbudget
