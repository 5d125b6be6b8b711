#include "glbudget/manifest/manifest.hpp"

#include <algorithm>

namespace glbudget::manifest {

int Manifest::find(const std::string& name) const {
  for (std::size_t i = 0; i < passes.size(); ++i) {
    if (passes[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

bool Pass::scales_targets() const {
  return std::any_of(levels.begin(), levels.end(), [](const Level& l) { return !l.targets.empty(); });
}

bool matches(const Match& match, uint64_t hash, const std::vector<std::string>& sources) {
  if (std::find(match.hashes.begin(), match.hashes.end(), hash) != match.hashes.end()) return true;
  for (const std::string& source : sources) {
    for (const std::string& substring : match.sources) {
      if (source.find(substring) != std::string::npos) return true;
    }
  }
  return false;
}

}  // namespace glbudget::manifest
