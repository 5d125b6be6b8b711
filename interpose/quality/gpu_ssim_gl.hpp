// The GL entry points GpuSsim calls, resolved through the caller's loader: inside the shim the
// loader returns the real driver's functions, so GpuSsim's calls never reach the shim's hooks.
#pragma once
#include <GL/glcorearb.h>

#include <string>

#include "gpu_ssim.hpp"

namespace glbudget::gpu_ssim_detail {

// X(member, type): every entry point, each loaded from "gl" #member.
// clang-format off
#define GLBUDGET_GPU_SSIM_GL_FUNCTIONS(X)                 \
  X(GetString, PFNGLGETSTRINGPROC)                        \
  X(GetStringi, PFNGLGETSTRINGIPROC)                      \
  X(GetIntegerv, PFNGLGETINTEGERVPROC)                    \
  X(GetIntegeri_v, PFNGLGETINTEGERI_VPROC)                \
  X(GetInteger64i_v, PFNGLGETINTEGER64I_VPROC)            \
  X(CreateShader, PFNGLCREATESHADERPROC)                  \
  X(ShaderSource, PFNGLSHADERSOURCEPROC)                  \
  X(CompileShader, PFNGLCOMPILESHADERPROC)                \
  X(GetShaderiv, PFNGLGETSHADERIVPROC)                    \
  X(GetShaderInfoLog, PFNGLGETSHADERINFOLOGPROC)          \
  X(DeleteShader, PFNGLDELETESHADERPROC)                  \
  X(CreateProgram, PFNGLCREATEPROGRAMPROC)                \
  X(AttachShader, PFNGLATTACHSHADERPROC)                  \
  X(LinkProgram, PFNGLLINKPROGRAMPROC)                    \
  X(GetProgramiv, PFNGLGETPROGRAMIVPROC)                  \
  X(GetProgramInfoLog, PFNGLGETPROGRAMINFOLOGPROC)        \
  X(DeleteProgram, PFNGLDELETEPROGRAMPROC)                \
  X(UseProgram, PFNGLUSEPROGRAMPROC)                      \
  X(GetUniformLocation, PFNGLGETUNIFORMLOCATIONPROC)      \
  X(Uniform1i, PFNGLUNIFORM1IPROC)                        \
  X(Uniform2i, PFNGLUNIFORM2IPROC)                        \
  X(GenBuffers, PFNGLGENBUFFERSPROC)                      \
  X(DeleteBuffers, PFNGLDELETEBUFFERSPROC)                \
  X(BindBuffer, PFNGLBINDBUFFERPROC)                      \
  X(BindBufferBase, PFNGLBINDBUFFERBASEPROC)              \
  X(BindBufferRange, PFNGLBINDBUFFERRANGEPROC)            \
  X(BufferData, PFNGLBUFFERDATAPROC)                      \
  X(MapBufferRange, PFNGLMAPBUFFERRANGEPROC)              \
  X(UnmapBuffer, PFNGLUNMAPBUFFERPROC)                    \
  X(GenSamplers, PFNGLGENSAMPLERSPROC)                    \
  X(DeleteSamplers, PFNGLDELETESAMPLERSPROC)              \
  X(SamplerParameteri, PFNGLSAMPLERPARAMETERIPROC)        \
  X(BindSampler, PFNGLBINDSAMPLERPROC)                    \
  X(ActiveTexture, PFNGLACTIVETEXTUREPROC)                \
  X(BindTexture, PFNGLBINDTEXTUREPROC)                    \
  X(IsTexture, PFNGLISTEXTUREPROC)                        \
  X(GetTexLevelParameteriv, PFNGLGETTEXLEVELPARAMETERIVPROC) \
  X(DispatchCompute, PFNGLDISPATCHCOMPUTEPROC)            \
  X(MemoryBarrier, PFNGLMEMORYBARRIERPROC)                \
  X(FenceSync, PFNGLFENCESYNCPROC)                        \
  X(ClientWaitSync, PFNGLCLIENTWAITSYNCPROC)              \
  X(DeleteSync, PFNGLDELETESYNCPROC)
// clang-format on

struct GlFunctions {
#define GLBUDGET_GPU_SSIM_MEMBER(name, type) type name = nullptr;
  GLBUDGET_GPU_SSIM_GL_FUNCTIONS(GLBUDGET_GPU_SSIM_MEMBER)
#undef GLBUDGET_GPU_SSIM_MEMBER
};

// Loads every entry point the loader has; false and the first missing name in *missing if
// one is missing (the others are loaded all the same).
bool load_gl_functions(GlProcLoader load, GlFunctions& gl, std::string* missing);

// What the current context offers GpuSsim's shaders.
struct GlCapabilities {
  bool es = false;
  int major = 0, minor = 0;
  std::string glsl_header;       // "#version ..." and the extensions and defines the shaders need
  bool srgb_decode_ext = false;  // EXT_texture_sRGB_decode: the sampler can pin the decode
};

// The capabilities of the current context, or false and why compute shaders are unavailable.
bool query_capabilities(const GlFunctions& gl, GlCapabilities& caps, std::string* why_not);

}  // namespace glbudget::gpu_ssim_detail
