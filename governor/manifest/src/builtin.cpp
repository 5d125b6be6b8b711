#include "glbudget/manifest/manifest.hpp"

namespace glbudget::manifest {

Pass builtin_resolution_pass() {
  Pass pass;
  pass.name = "resolution";
  Target window;
  window.kind = Target::Kind::default_framebuffer;
  for (const auto& [name, scale] : {std::pair{"100%", 1.0}, {"80%", 0.8}, {"60%", 0.6}, {"50%", 0.5}}) {
    Level level;
    level.name = name;
    level.scale = scale;
    if (scale < 1.0) level.targets = {window};
    pass.levels.push_back(level);
  }
  return pass;
}

Manifest with_resolution_pass(std::optional<Manifest> m) {
  Manifest result = m ? std::move(*m) : Manifest{};
  if (result.find("resolution") >= 0) return result;
  Pass resolution = builtin_resolution_pass();
  for (const Pass& pass : result.passes) {
    if (!pass.match.empty()) resolution.scales.push_back(pass.name);
  }
  result.passes.insert(result.passes.begin(), std::move(resolution));
  return result;
}

}  // namespace glbudget::manifest
