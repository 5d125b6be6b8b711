#include "calibrate_errors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "glbudget/analysis/frame_log.hpp"
#include "glbudget/model/variant_table.hpp"

namespace glbudget::cli {

std::optional<ErrorRatios> error_ratios_from_log(const std::string& log_path, const model::ConfigurationSpace& space) {
  const std::optional<analysis::FrameLog> log = analysis::read_frame_log_file(log_path);  // says why when it fails
  if (!log) return std::nullopt;
  std::map<std::pair<std::string, int>, std::pair<double, int>> sums;
  for (const analysis::LoggedFrame& frame : log->frames) {
    std::istringstream streams(frame.probe_streams);
    for (std::string stream; std::getline(streams, stream, ';');) {
      const std::size_t equals = stream.find('=');
      if (equals == std::string::npos) continue;
      const std::optional<model::Configuration> levels =
          model::parse_configuration(std::string_view(stream).substr(0, equals), space);
      char* end = nullptr;
      const double error = std::strtod(stream.c_str() + equals + 1, &end);
      if (!levels || *end || !std::isfinite(error)) continue;
      const int pass = model::only_pass_changed(*levels);
      if (pass < 0) continue;
      auto& sum =
          sums[{space.passes()[static_cast<std::size_t>(pass)].pass, (*levels)[static_cast<std::size_t>(pass)]}];
      sum.first += std::max(0.0, error);
      ++sum.second;
    }
  }
  ErrorRatios out;
  for (const auto& [key, sum] : sums) out.measured[key] = {sum.first / sum.second, sum.second};
  for (const model::PassVariants& pass : space.passes()) {
    const int lmax = static_cast<int>(pass.levels.size()) - 1;
    const auto cheapest = out.measured.find({pass.pass, lmax});
    if (lmax < 1 || cheapest == out.measured.end() || cheapest->second.mean_error < 1e-6) continue;
    for (int l = 1; l <= lmax; ++l)
      if (const auto level = out.measured.find({pass.pass, l}); level != out.measured.end())
        out.ratios[{pass.pass, l}] = std::clamp(level->second.mean_error / cheapest->second.mean_error, 0.0, 1.0);
  }
  return out;
}

std::string best_configuration(const manifest::Manifest& m) {
  std::string best;
  for (std::size_t i = 0; i < m.passes.size(); ++i) best += i ? ",0" : "0";
  return best;
}

std::uint64_t error_run_frames(const manifest::Manifest& m, unsigned per_level) {
  std::uint64_t levels = 0;
  for (const manifest::Pass& pass : m.passes) levels += pass.levels.empty() ? 0 : pass.levels.size() - 1;
  return 2 * levels * per_level + 8;
}

}  // namespace glbudget::cli
