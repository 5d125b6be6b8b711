#include "glbudget/manifest/manifest.hpp"

#include <array>

namespace glbudget::manifest {
namespace {
constexpr std::array<const char*, 6> kStageNames = {"vertex",   "tess_control", "tess_evaluation",
                                                    "geometry", "fragment",     "compute"};
}  // namespace

const char* stage_name(Stage stage) { return kStageNames[static_cast<std::size_t>(stage)]; }

std::optional<Stage> parse_stage(const std::string& name) {
  for (std::size_t i = 0; i < kStageNames.size(); ++i) {
    if (name == kStageNames[i]) return static_cast<Stage>(i);
  }
  return std::nullopt;
}

}  // namespace glbudget::manifest
