#pragma once
// Beyond the paper: how many fragments a pass really draws at each level of a pass that scales
// it (paper §7: "the number of fragments for other passes are proportionally scaled").
//
// A variant table declares a render scale's or a shadow map's area (0.8 -> 0.64), and that is
// the prior. Measured, fragments do not follow the area: every triangle's edge is shaded in
// whole 2x2 quads, and the smaller the target the larger that share. The demo's Hall at
// 320x180 draws 0.77 and 0.48 of its base pass's full-scale fragments at render scales 0.8 and
// 0.6, not 0.64 and 0.36, so a prediction from the small scale back to the full one overshot
// by a third. Once the history holds frames at a level, its measured ratio replaces the area.
#include <cstddef>
#include <map>
#include <span>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/configured_sample.hpp"

namespace glbudget::model {

class FragmentScales {
 public:
  FragmentScales() = default;
  // The table's declared scales.
  explicit FragmentScales(const ConfigurationSpace& space);

  // The factor on pass `pass`'s fragments when pass `scaler` is at `level` (1 where the
  // scaler does not scale it).
  double at(std::size_t pass, std::size_t scaler, int level) const;
  void set(std::size_t pass, std::size_t scaler, int level, double scale);
  bool measured(std::size_t pass, std::size_t scaler, int level) const;

 private:
  struct Levels {
    std::vector<double> scale;
    std::vector<bool> measured;
  };
  std::vector<std::map<std::size_t, Levels>> scales_;  // [pass][scaler]
};

// The declared scales, with those measured in `history` where a pass has one scaler and
// at least `min_frames` frames drew it at a level: each such level's mean fragments relative to
// those at the measured level of largest declared scale, which keeps its declared value.
//
// With `known` (what earlier histories measured), levels the history does not hold keep their
// scale there, and the anchor keeps its known scale rather than the declared one. A history
// that has moved on from a level says nothing new of it: on the demo's Valley the shadow map
// at 512 draws 0.147 of the fragments it draws at 2048 (a depth pass's overdraw does not
// follow the area), and once the frames at 2048 left the history the declared 0.0625 came
// back, predicting the best configuration's shadow pass at 2.35 times its fragments and the
// best itself 5.7 W over what it draws.
inline constexpr std::size_t kMinScaleFrames = 5;
FragmentScales measure_fragment_scales(std::span<const ConfiguredSample> history, const ConfigurationSpace& space,
                                       std::size_t min_frames = kMinScaleFrames, const FragmentScales* known = nullptr);

}  // namespace glbudget::model
