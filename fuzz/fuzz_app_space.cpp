// Fuzz target: the app-coordinates rewrite (instrument/app_space.hpp), run on each fragment
// shader of a program the shim may draw into scaled render targets.
// Input: byte 0 bit 0: pass an (empty) driver extension list; the rest: the shader's source.
#include <cstdint>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "glbudget/instrument/app_space.hpp"

namespace instrument = glbudget::instrument;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const std::optional<std::vector<std::string>> extensions =
      (data[0] & 1) ? std::optional<std::vector<std::string>>(std::vector<std::string>{}) : std::nullopt;
  const std::string source(reinterpret_cast<const char*>(data + 1), size - 1);
  const instrument::AppSpaceResult r = instrument::to_app_space(source, extensions);
  // What callers rely on: a rewrite has a source that declares what it uses; a refusal says why;
  // a shader that needs nothing is left alone.
  if (r.ok && (!r.needed || r.source.empty())) std::abort();
  if (r.ok && r.frag_coord && r.source.find(instrument::kFragRatioUniform) == std::string::npos) std::abort();
  if (r.ok)
    for (const instrument::AppSpaceSampler& s : r.samplers)
      if (r.source.find(instrument::kSamplerSizePrefix + s.name) == std::string::npos) std::abort();
  if (r.needed && !r.ok && r.error.empty()) std::abort();
  if (!r.needed && (r.ok || !r.source.empty() || r.unsupported)) std::abort();
  if (r.unsupported && r.ok) std::abort();
  return 0;
}
