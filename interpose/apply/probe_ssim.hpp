// Where a probe frame's images are compared (GLBUDGET_PROBE_SSIM; DESIGN.md, "Quality
// probes"): in the context's own compute shaders (quality/gpu_ssim.hpp), the results read back
// a frame or more later behind a fence, or on the governor thread from the images read back
// (governor/quality's CPU path), for contexts without compute shaders. Both compute the same
// SSIM (docs/ssim.md).
//
// auto, the default, takes the GPU unless the renderer is a software rasterizer: there the
// "GPU" is the CPU cores the app draws on, and the compute shaders run inside the app's swap
// where the governor thread's CPU path runs beside the app (docs/probes.md measures both).
#pragma once
#include <memory>

#include "gpu_ssim.hpp"

namespace glbudget {

struct GlCaps;

// For the context current now: its GpuSsim, or null where probe frames are compared on the CPU
// (GLBUDGET_PROBE_SSIM=cpu; auto on a software rasterizer; no compute shaders, or
// GL_ARB_compute_shader hidden by GLBUDGET_TEST_HIDE_EXTENSIONS; the shaders did not build).
// Where gpu was asked for and cannot be had, one glbudget: line says why.
std::unique_ptr<GpuSsim> make_probe_ssim();

// The renderer draws on the CPU (llvmpipe, softpipe, swrast, SwiftShader, WARP, Apple's).
bool software_renderer(const char* renderer);

}  // namespace glbudget
