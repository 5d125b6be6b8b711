#include "probe_ssim.hpp"

#include <string>

#include "apply_gl.hpp"
#include "hook_table.hpp"
#include "messages.hpp"
#include "options.hpp"

namespace glbudget {

bool software_renderer(const char* renderer) {
  if (!renderer) return false;
  const std::string r(renderer);
  for (const char* name : {"llvmpipe", "softpipe", "swrast", "Software Rasterizer", "SwiftShader",
                           "Microsoft Basic Render", "Apple Software Renderer"})
    if (r.find(name) != std::string::npos) return true;
  return false;
}

std::unique_ptr<GpuSsim> make_probe_ssim() {
  const Options::ProbeSsim mode = options().probe_ssim;
  if (mode == Options::ProbeSsim::kCpu) return nullptr;
  const bool asked = mode == Options::ProbeSsim::kGpu;
  auto cannot = [&](const std::string& why) -> std::unique_ptr<GpuSsim> {
    if (asked) say_once("probe-ssim", "GLBUDGET_PROBE_SSIM=gpu: " + why + "; probe frames are compared on the CPU");
    return nullptr;
  };
  if (extension_hidden("GL_ARB_compute_shader"))
    return cannot("compute shaders hidden (GLBUDGET_TEST_HIDE_EXTENSIONS)");
  if (!asked) {
    using GetString = const unsigned char*(APIENTRYP)(GLenum);
    auto get_string = reinterpret_cast<GetString>(resolve_gl("glGetString"));
    const unsigned char* renderer = get_string ? get_string(GL_RENDERER) : nullptr;
    if (software_renderer(reinterpret_cast<const char*>(renderer))) return nullptr;
  }
  std::string why;
  std::unique_ptr<GpuSsim> gpu = GpuSsim::create(&resolve_gl, &why);
  if (!gpu) return cannot("no GPU SSIM in this context (" + why + ")");
  return gpu;
}

}  // namespace glbudget
