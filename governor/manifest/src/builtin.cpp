#include "glbudget/manifest/manifest.hpp"

namespace glbudget::manifest {

Pass builtin_resolution_pass() {
  Pass pass;
  pass.name = "resolution";
  // The window, and the app's framebuffers of the window's size: most apps draw their scene
  // off screen at the window's size and only compose it into the window, so the window alone
  // would scale little of the work.
  Target window, window_sized;
  window.kind = Target::Kind::default_framebuffer;
  window_sized.kind = Target::Kind::window_sized;
  for (const auto& [name, scale] : {std::pair{"100%", 1.0}, {"80%", 0.8}, {"60%", 0.6}, {"50%", 0.5}}) {
    Level level;
    level.name = name;
    level.scale = scale;
    if (scale < 1.0) level.targets = {window, window_sized};
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
