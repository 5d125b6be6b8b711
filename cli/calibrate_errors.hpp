#pragma once
// The ratios k = e_i(l) / e_i(lmax) of `glbudget calibrate --app` (paper §6.2): the app runs at
// its best with quality probes every other frame at every level of every pass in turn
// (GLBUDGET_PROBE_LEVELS=all), and the errors the shim logs per probe stream
// (probe_streams: "levels=error") are averaged per pass and level.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>

#include "glbudget/manifest/manifest.hpp"
#include "glbudget/model/configuration_space.hpp"

namespace glbudget::cli {

struct LevelErrors {
  double mean_error = 0.0;  // 1 - SSIM against the best configuration, over its probe frames
  int probes = 0;
};

struct ErrorRatios {
  std::map<std::pair<std::string, int>, LevelErrors> measured;  // by pass name and level >= 1
  std::map<std::pair<std::string, int>, double> ratios;         // k, for passes whose cheapest level measured an error
};

// From a frame log's probe_streams column (each probe frame once): every stream that differs
// from the best in one pass of `space`. k of a pass's levels: their mean error over the cheapest
// level's, within [0, 1]; none for a pass whose cheapest level's error is below 1e-6 (nothing
// to scale) or was not probed. nullopt when the log cannot be read (the reader says why).
std::optional<ErrorRatios> error_ratios_from_log(const std::string& log_path, const model::ConfigurationSpace& space);

// GLBUDGET_FORCE's best configuration ("0,0,0") and the probe frames wanted: `per_level` of
// each level below the best, every other frame, and a few frames for the last read-backs.
std::string best_configuration(const manifest::Manifest& m);
std::uint64_t error_run_frames(const manifest::Manifest& m, unsigned per_level);

}  // namespace glbudget::cli
