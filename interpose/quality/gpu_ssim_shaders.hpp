// GpuSsim's compute shaders (GLSL source) and how they are built.
//
//   downscale  (scale 2, 4)  textures -> box-averaged luma of A and B, one SSBO
//   ssim       tiles of 16x16 map positions: luma with a 5-pixel halo in shared memory, an
//              11-tap horizontal pass keeping the five moments, an 11-tap vertical pass (two
//              map rows per invocation, sharing their rows), the SSIM map, and the tile's sum
//              of 1 - SSIM as one partial per workgroup
//   reduce     one workgroup: the sum of the partials, one float in a result buffer
#pragma once
#include <string>

#include "gpu_ssim_gl.hpp"

namespace glbudget::gpu_ssim_detail {

inline constexpr int kTile = 16;                          // map positions per tile side
inline constexpr int kGroupWidth = 16, kGroupHeight = 8;  // 128 invocations: GLES 3.1's minimum
inline constexpr int kReduceGroup = 128;
// The shaders assume it: one invocation per tile column and two map rows per invocation, and
// a 128-wide tree for the group sums.
static_assert(kGroupWidth == kTile && 2 * kGroupHeight == kTile);
static_assert(kGroupWidth * kGroupHeight == 128 && kReduceGroup == 128);

// Where the ssim shader reads luma: straight from the two textures (scale 1), or from the
// downscale shader's SSBO.
enum class LumaSource { kTextures, kBuffer };

std::string downscale_shader_source(const GlCapabilities& caps);
std::string ssim_shader_source(const GlCapabilities& caps, LumaSource source);
std::string reduce_shader_source(const GlCapabilities& caps);

// Compiles and links one compute shader: the program, or 0 and the driver's log in *error.
GLuint build_compute_program(const GlFunctions& gl, const std::string& source, std::string* error);

}  // namespace glbudget::gpu_ssim_detail
