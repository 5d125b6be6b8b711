#include "glbudget/model/fragment_scales.hpp"

#include <cmath>

namespace glbudget::model {

FragmentScales::FragmentScales(const ConfigurationSpace& space) : scales_(space.pass_count()) {
  for (std::size_t p = 0; p < space.pass_count(); ++p) {
    for (std::size_t j : space.scaled_by(p)) {
      Levels& levels = scales_[j][p];
      for (const VariantCost& level : space.passes()[p].levels) levels.scale.push_back(level.fragment_scale);
      levels.measured.assign(levels.scale.size(), false);
    }
  }
}

double FragmentScales::at(std::size_t pass, std::size_t scaler, int level) const {
  if (pass >= scales_.size()) return 1.0;
  const auto it = scales_[pass].find(scaler);
  if (it == scales_[pass].end() || level < 0 || static_cast<std::size_t>(level) >= it->second.scale.size()) return 1.0;
  return it->second.scale[static_cast<std::size_t>(level)];
}

void FragmentScales::set(std::size_t pass, std::size_t scaler, int level, double scale) {
  if (pass >= scales_.size()) return;
  const auto it = scales_[pass].find(scaler);
  if (it == scales_[pass].end() || level < 0 || static_cast<std::size_t>(level) >= it->second.scale.size()) return;
  it->second.scale[static_cast<std::size_t>(level)] = scale;
  it->second.measured[static_cast<std::size_t>(level)] = true;
}

bool FragmentScales::measured(std::size_t pass, std::size_t scaler, int level) const {
  if (pass >= scales_.size()) return false;
  const auto it = scales_[pass].find(scaler);
  if (it == scales_[pass].end() || level < 0 || static_cast<std::size_t>(level) >= it->second.measured.size())
    return false;
  return it->second.measured[static_cast<std::size_t>(level)];
}

FragmentScales measure_fragment_scales(std::span<const ConfiguredSample> history, const ConfigurationSpace& space,
                                       std::size_t min_frames, const FragmentScales* known) {
  FragmentScales scales = known ? *known : FragmentScales(space);
  for (std::size_t j = 0; j < space.pass_count(); ++j) {
    const std::vector<std::size_t>& scalers = space.scalers_of(j);
    // With two scalers a level's frames mix the other's levels: keep the declared scales.
    if (scalers.size() != 1) continue;
    const std::size_t p = scalers.front();
    const std::vector<VariantCost>& levels = space.passes()[p].levels;
    std::vector<double> sum(levels.size(), 0.0);
    std::vector<std::size_t> frames(levels.size(), 0);
    for (const ConfiguredSample& s : history) {
      if (!space.contains(s.configuration)) continue;
      if (!space.passes()[j].levels[static_cast<std::size_t>(s.configuration[j])].draws) continue;
      for (const PassFrame& pass : s.sample.passes) {
        const double f = pass.counts.fragments;
        if (pass.pass != j || !std::isfinite(f) || !(f > 0.0)) continue;
        const auto l = static_cast<std::size_t>(s.configuration[p]);
        sum[l] += f;
        ++frames[l];
      }
    }
    // The anchor: of the measured levels, the one declared largest keeps its scale (declared,
    // or as known).
    std::size_t anchor = levels.size();
    for (std::size_t l = 0; l < levels.size(); ++l) {
      if (frames[l] < min_frames || !(levels[l].fragment_scale > 0.0)) continue;
      if (anchor == levels.size() || levels[l].fragment_scale > levels[anchor].fragment_scale) anchor = l;
    }
    if (anchor == levels.size()) continue;
    const double anchor_mean = sum[anchor] / static_cast<double>(frames[anchor]);
    const double anchor_scale = scales.at(j, p, static_cast<int>(anchor));
    for (std::size_t l = 0; l < levels.size(); ++l) {
      if (l == anchor || frames[l] < min_frames) continue;
      const double mean = sum[l] / static_cast<double>(frames[l]);
      scales.set(j, p, static_cast<int>(l), anchor_scale * mean / anchor_mean);
    }
  }
  return scales;
}

}  // namespace glbudget::model
