// Fuzz target: shader instrumentation (GLSL in, GLSL out through glslang), as the shim runs
// it at every glCompileShader of the app.
// Input: 2 header bytes, then the shader's source.
//   byte 0: bits 0-2 the stage (mod 6: vertex, tess_control, tess_evaluation, geometry,
//           fragment, compute); bit 3: pass a driver extension list; bit 4: hand the source
//           over as two strings (split in the middle), as glShaderSource may.
//   byte 1: the counter block's binding.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "glbudget/instrument/instrument.hpp"

namespace instrument = glbudget::instrument;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return -1;
  const std::uint8_t flags = data[0];
  const int binding = data[1];
  const std::string source(reinterpret_cast<const char*>(data) + 2, size - 2);

  instrument::InstrumentRequest request;
  request.stage = static_cast<instrument::Stage>((flags & 7) % instrument::kStageCount);
  request.ssbo_binding = binding;
  if (flags & 16) {
    request.sources = {source.substr(0, source.size() / 2), source.substr(source.size() / 2)};
  } else {
    request.sources = {source};
  }
  if (flags & 8) {
    request.driver_extensions =
        std::vector<std::string>{"GL_ARB_shader_storage_buffer_object", "GL_ARB_gpu_shader5", "GL_EXT_gpu_shader4",
                                 "GL_ARB_separate_shader_objects", "GL_ARB_explicit_attrib_location"};
  }
  const instrument::InstrumentResult result = instrument::instrument_shader(request);
  // What the shim relies on: a failure says why, a success gives a source.
  if (result.ok == result.instrumented_source.empty()) std::abort();
  if (!result.ok && result.error.empty()) std::abort();
  return 0;
}
