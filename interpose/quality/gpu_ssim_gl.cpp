#include "gpu_ssim_gl.hpp"

#include <cstdio>
#include <cstring>
#include <set>

namespace glbudget::gpu_ssim_detail {

bool load_gl_functions(GlProcLoader load, GlFunctions& gl, std::string* missing) {
  bool complete = true;
#define GLBUDGET_GPU_SSIM_LOAD(name, type)            \
  gl.name = reinterpret_cast<type>(load("gl" #name)); \
  if (!gl.name && complete) {                         \
    complete = false;                                 \
    if (missing) *missing = "gl" #name;               \
  }
  GLBUDGET_GPU_SSIM_GL_FUNCTIONS(GLBUDGET_GPU_SSIM_LOAD)
#undef GLBUDGET_GPU_SSIM_LOAD
  return complete;
}

namespace {

void set_why(std::string* why_not, std::string text) {
  if (why_not) *why_not = std::move(text);
}

std::set<std::string> extensions(const GlFunctions& gl) {
  std::set<std::string> names;
  GLint count = 0;
  gl.GetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i)
    if (const GLubyte* name = gl.GetStringi(GL_EXTENSIONS, static_cast<GLuint>(i)))
      names.insert(reinterpret_cast<const char*>(name));
  return names;
}

}  // namespace

bool query_capabilities(const GlFunctions& gl, GlCapabilities& caps, std::string* why_not) {
  const GLubyte* version_bytes = gl.GetString(GL_VERSION);
  if (!version_bytes) {
    set_why(why_not, "no current OpenGL context (glGetString(GL_VERSION) returned null)");
    return false;
  }
  const std::string version = reinterpret_cast<const char*>(version_bytes);
  constexpr const char* kEsPrefix = "OpenGL ES";
  caps.es = version.rfind(kEsPrefix, 0) == 0;
  // "4.5 (Core Profile) Mesa 22.3.6" or "OpenGL ES 3.2 Mesa 22.3.6" (ES-CM/ES-CL for 1.x).
  const char* numbers = version.c_str() + (caps.es ? std::strcspn(version.c_str(), "0123456789") : 0);
  if (std::sscanf(numbers, "%d.%d", &caps.major, &caps.minor) != 2) {
    set_why(why_not, "cannot parse the OpenGL version \"" + version + "\"");
    return false;
  }
  const std::set<std::string> ext = extensions(gl);
  const auto has = [&](const char* name) { return ext.count(name) != 0; };
  caps.srgb_decode_ext = has("GL_EXT_texture_sRGB_decode");
  const int v = caps.major * 10 + caps.minor;
  if (caps.es) {
    if (v < 31) {
      set_why(why_not, "compute shaders need OpenGL ES 3.1, the context is \"" + version + "\"");
      return false;
    }
    // 'precise' keeps the compiler from fusing one side of SSIM's ratio and not the other
    // (identical images must give exactly 1); ES has it from 3.2 or with gpu_shader5.
    if (v >= 32) {
      caps.glsl_header = "#version 320 es\n#define PRECISE precise\n";
    } else if (has("GL_OES_gpu_shader5") || has("GL_EXT_gpu_shader5")) {
      caps.glsl_header = std::string("#version 310 es\n#extension ") +
                         (has("GL_OES_gpu_shader5") ? "GL_OES_gpu_shader5" : "GL_EXT_gpu_shader5") +
                         " : require\n#define PRECISE precise\n";
    } else {
      caps.glsl_header = "#version 310 es\n#define PRECISE\n";
    }
    caps.glsl_header += "precision highp float;\nprecision highp int;\nprecision highp sampler2D;\n";
    return true;
  }
  if (v >= 43) {
    caps.glsl_header = "#version 430 core\n#define PRECISE precise\n";
    return true;
  }
  // GLSL 4.20 has layout(binding) and memory barriers; compute and SSBOs come as extensions.
  if (v >= 42 && has("GL_ARB_compute_shader") && has("GL_ARB_shader_storage_buffer_object")) {
    caps.glsl_header =
        "#version 420 core\n#extension GL_ARB_compute_shader : require\n"
        "#extension GL_ARB_shader_storage_buffer_object : require\n#define PRECISE precise\n";
    return true;
  }
  set_why(why_not,
          "compute shaders need OpenGL 4.3 (or 4.2 with ARB_compute_shader and "
          "ARB_shader_storage_buffer_object), the context is \"" +
              version + "\"");
  return false;
}

}  // namespace glbudget::gpu_ssim_detail
