#pragma once
// The search space of paper §3: a configuration assigns a quality level to each pass
// (level 0 is the best); the space is the product of the passes' levels.
#include <cstddef>
#include <string>
#include <vector>

namespace glbudget::model {

// Per-invocation cost of one shader variant, measured by the shader instrumentation: average
// executed instructions per vertex- and fragment-shader invocation, and texel accesses per
// fragment invocation (paper §5.4; vertex shaders are taken not to sample textures).
struct VariantCost {
  double ins_v = 0.0;
  double ins_f = 0.0;
  double tex_f = 0.0;
  // Levels that change how many fragments are drawn rather than what each costs: the paper's
  // resolution "pass" (render scale 0.8 draws 0.64 of the fragments of the passes it scales)
  // or a shadow-map size (its own pass). Relative to a level at 1.
  double fragment_scale = 1.0;
  // false: the level skips the pass's draws (reflections or antialiasing off).
  bool draws = true;
};

struct PassVariants {
  std::string pass;
  std::vector<VariantCost> levels;  // best first; at least one
  // Passes whose fragment counts this pass's fragment_scale multiplies: itself for a shadow
  // map's size, the scene passes for the render scale. Empty: it scales nothing.
  std::vector<std::string> scales;
};

using Configuration = std::vector<int>;  // level per pass, in ConfigurationSpace order

// The one pass whose level is not its best (0): what a probe stream s_i^l measures; -1 when
// none is, or several are.
inline int only_pass_changed(const Configuration& configuration) {
  int pass = -1;
  for (std::size_t i = 0; i < configuration.size(); ++i) {
    if (configuration[i] == 0) continue;
    if (pass >= 0) return -1;
    pass = static_cast<int>(i);
  }
  return pass;
}

class ConfigurationSpace {
 public:
  ConfigurationSpace() = default;
  // Passes without levels get a single zero-cost level, so the space is never empty.
  explicit ConfigurationSpace(std::vector<PassVariants> passes);

  const std::vector<PassVariants>& passes() const { return passes_; }
  std::size_t pass_count() const { return passes_.size(); }
  // PassVariants::scales by index, resolved once: the passes whose fragments pass p's levels
  // scale, and the passes that scale pass j's (each ascending; names of no pass are dropped).
  const std::vector<std::size_t>& scaled_by(std::size_t p) const { return scaled_by_[p]; }
  const std::vector<std::size_t>& scalers_of(std::size_t j) const { return scalers_of_[j]; }
  std::size_t size() const { return size_; }

  // Row-major: the last pass changes fastest. index_of(decode(i)) == i.
  std::size_t index_of(const Configuration& configuration) const;
  Configuration decode(std::size_t index) const;
  bool contains(const Configuration& configuration) const;
  // Every pass at its last level.
  Configuration cheapest() const;
  // The level `configuration` draws pass `pass` at; nullptr for a pass outside the space (or
  // the configuration).
  const VariantCost* level_of(std::size_t pass, const Configuration& configuration) const {
    if (pass >= passes_.size() || pass >= configuration.size()) return nullptr;
    return &passes_[pass].levels[static_cast<std::size_t>(configuration[pass])];
  }

 private:
  std::vector<PassVariants> passes_;
  std::vector<std::vector<std::size_t>> scaled_by_, scalers_of_;
  std::vector<std::size_t> strides_;
  std::size_t size_ = 1;
};

}  // namespace glbudget::model
