#include "calibrate_errors.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

namespace glbudget::cli {

namespace {

std::vector<std::string> split(const std::string& text, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, separator)) parts.push_back(part);
  if (!text.empty() && text.back() == separator) parts.emplace_back();
  return parts;
}

// "0:0:2" as levels; nullopt unless one level per pass of `m`, each within its pass.
std::optional<std::vector<int>> parse_levels(const std::string& text, const manifest::Manifest& m) {
  const std::vector<std::string> parts = split(text, ':');
  if (parts.size() != m.passes.size()) return std::nullopt;
  std::vector<int> levels;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    char* end = nullptr;
    const long l = std::strtol(parts[i].c_str(), &end, 10);
    if (parts[i].empty() || *end || l < 0 || l >= static_cast<long>(m.passes[i].levels.size())) return std::nullopt;
    levels.push_back(static_cast<int>(l));
  }
  return levels;
}

}  // namespace

std::optional<ErrorRatios> error_ratios_from_log(const std::string& log_path, const manifest::Manifest& m,
                                                 std::string* why_not) {
  std::ifstream in(log_path);
  std::string header;
  if (!in || !std::getline(in, header)) {
    if (why_not) *why_not = "no frame log at " + log_path;
    return std::nullopt;
  }
  const std::vector<std::string> columns = split(header, ',');
  const auto column = [&](const char* name) {
    return static_cast<std::size_t>(std::find(columns.begin(), columns.end(), name) - columns.begin());
  };
  const std::size_t frame_at = column("frame"), context_at = column("context"), streams_at = column("probe_streams");
  if (streams_at == columns.size() || frame_at == columns.size()) {
    if (why_not) *why_not = "the frame log has no probe_streams column (a shim older than this command?)";
    return std::nullopt;
  }
  std::map<std::pair<std::string, int>, std::pair<double, int>> sums;
  std::set<std::pair<std::string, std::string>> seen;  // (context, frame): its rows repeat the streams
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> fields = split(line, ',');
    if (fields.size() != columns.size() || fields[streams_at].empty()) continue;
    const std::string context = context_at < fields.size() ? fields[context_at] : "";
    if (!seen.insert({context, fields[frame_at]}).second) continue;
    for (const std::string& stream : split(fields[streams_at], ';')) {
      const std::size_t equals = stream.find('=');
      if (equals == std::string::npos) continue;
      const std::optional<std::vector<int>> levels = parse_levels(stream.substr(0, equals), m);
      char* end = nullptr;
      const double error = std::strtod(stream.c_str() + equals + 1, &end);
      if (!levels || *end || !std::isfinite(error)) continue;
      int pass = -1;
      for (std::size_t i = 0; i < levels->size(); ++i)
        if ((*levels)[i] != 0) pass = pass < 0 ? static_cast<int>(i) : -2;
      if (pass < 0) continue;
      auto& sum = sums[{m.passes[static_cast<std::size_t>(pass)].name, (*levels)[static_cast<std::size_t>(pass)]}];
      sum.first += std::max(0.0, error);
      ++sum.second;
    }
  }
  ErrorRatios out;
  for (const auto& [key, sum] : sums) out.measured[key] = {sum.first / sum.second, sum.second};
  for (const manifest::Pass& pass : m.passes) {
    const int lmax = static_cast<int>(pass.levels.size()) - 1;
    const auto cheapest = out.measured.find({pass.name, lmax});
    if (lmax < 1 || cheapest == out.measured.end() || cheapest->second.mean_error < 1e-6) continue;
    for (int l = 1; l <= lmax; ++l)
      if (const auto level = out.measured.find({pass.name, l}); level != out.measured.end())
        out.ratios[{pass.name, l}] = std::clamp(level->second.mean_error / cheapest->second.mean_error, 0.0, 1.0);
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
