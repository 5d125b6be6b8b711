#include "glbudget/analysis/calibration.hpp"

#include <algorithm>
#include <cmath>

namespace glbudget::analysis {

using namespace glbudget::model;
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double median(std::vector<double> values) {
  if (values.empty()) return kNaN;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (upper + *std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid)));
}

std::vector<CalibrationPoint> usable_sorted(std::span<const CalibrationPoint> curve) {
  std::vector<CalibrationPoint> points;
  for (const CalibrationPoint& p : curve)
    if (std::isfinite(p.count) && p.count > 0.0 && std::isfinite(p.power_w)) points.push_back(p);
  std::stable_sort(points.begin(), points.end(),
                   [](const CalibrationPoint& a, const CalibrationPoint& b) { return a.count < b.count; });
  return points;
}

// The rms of the points about their monotone fit in the curve's upper half (at least half-way
// up its rise): what the fit had to smooth away where the load, and with it the noise, is high.
double noise_about(std::span<const CalibrationPoint> points, const MonotoneCurve& fit, double idle_w, double rise) {
  double sum = 0.0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!(fit.power_w[i] >= idle_w + 0.5 * rise)) continue;
    sum += std::pow(points[i].power_w - fit.power_w[i], 2);
    ++n;
  }
  return n == 0 ? 0.0 : std::sqrt(sum / static_cast<double>(n));
}

// The gain over the last two steps runs from the fit three steps from the end to the plateau
// (the median of the last three): one high last step alone is not a rise.
bool flattened(std::span<const CalibrationPoint> points, const MonotoneCurve& fit, double idle_w, double plateau_w,
               const SaturationRule& rule) {
  const std::size_t n = fit.power_w.size();
  if (n < 3) return false;
  const double gain = plateau_w - fit.power_w[n - 3];
  const double rise = std::max(plateau_w - idle_w, 0.0);
  return gain <= std::max(rule.flat_gain_share * rise, 2.0 * noise_about(points, fit, idle_w, rise));
}

}  // namespace

StepMeasurement measure_step(std::span<const LoggedFrame> frames, double start_ns, double end_ns) {
  StepMeasurement m;
  double energy_j = 0.0, seconds = 0.0;
  std::vector<double> counts[3];
  for (const LoggedFrame& f : frames) {
    if (!(f.time_ns > start_ns && f.time_ns <= end_ns)) continue;
    // The shim charges a frame the energy since the previous swap: power = energy / that time.
    if (std::isfinite(f.power_w) && f.power_w > 0.0 && std::isfinite(f.energy_j) && f.energy_j >= 0.0) {
      energy_j += f.energy_j;
      seconds += f.energy_j / f.power_w;
      ++m.frames;
    }
    double sum[3] = {0.0, 0.0, 0.0};
    for (const LoggedPass& p : f.passes) {
      sum[0] += p.counts.batches;
      sum[1] += p.counts.vertices;
      sum[2] += p.counts.fragments;
    }
    for (int i = 0; i < 3; ++i)
      if (!f.passes.empty() && std::isfinite(sum[i])) counts[i].push_back(sum[i]);
  }
  if (seconds > 0.0) m.power_w = energy_j / seconds;
  m.batches = median(counts[0]);
  m.vertices = median(counts[1]);
  m.fragments = median(counts[2]);
  return m;
}

const char* to_string(SaturationKind kind) {
  switch (kind) {
    case SaturationKind::saturated:
      return "saturated";
    case SaturationKind::saturated_at_start:
      return "saturated at the first step";
    case SaturationKind::frame_limited:
      return "frame-limited (still rising once frames were late)";
    case SaturationKind::still_rising:
      return "still rising";
    case SaturationKind::flat:
      return "flat";
    case SaturationKind::no_data:
      return "no data";
  }
  return "?";
}

MonotoneCurve monotone_fit(std::span<const CalibrationPoint> curve) {
  const std::vector<CalibrationPoint> points = usable_sorted(curve);
  // Pool adjacent violators: blocks of (mean, size), merged while a block is below the one before.
  std::vector<std::pair<double, std::size_t>> blocks;
  for (const CalibrationPoint& p : points) {
    blocks.emplace_back(p.power_w, 1);
    while (blocks.size() > 1 && blocks[blocks.size() - 2].first > blocks.back().first) {
      const auto [mean, size] = blocks.back();
      blocks.pop_back();
      auto& previous = blocks.back();
      previous.first = (previous.first * static_cast<double>(previous.second) + mean * static_cast<double>(size)) /
                       static_cast<double>(previous.second + size);
      previous.second += size;
    }
  }
  MonotoneCurve fit;
  for (const CalibrationPoint& p : points) fit.count.push_back(p.count);
  for (const auto& [mean, size] : blocks) fit.power_w.insert(fit.power_w.end(), size, mean);
  return fit;
}

double plateau_power(std::span<const CalibrationPoint> curve) {
  const std::vector<CalibrationPoint> points = usable_sorted(curve);
  std::vector<double> tail;
  for (std::size_t i = points.size() > 3 ? points.size() - 3 : 0; i < points.size(); ++i)
    tail.push_back(points[i].power_w);
  return median(tail);
}

Saturation find_saturation(std::span<const CalibrationPoint> curve, double idle_w, double range_w,
                           const SaturationRule& rule) {
  const std::vector<CalibrationPoint> points = usable_sorted(curve);
  Saturation s;
  if (points.empty()) return s;
  const MonotoneCurve fit = monotone_fit(points);
  s.plateau_w = plateau_power(points);
  const double rise = s.plateau_w - idle_w;
  s.count = fit.count.back();
  if (!(rise > rule.min_rise_share * range_w) || !(rise > 0.0)) {
    s.kind = SaturationKind::flat;
    return s;
  }
  const std::size_t n = points.size();
  const bool late = n >= 2 && points[n - 1].late && points[n - 2].late;
  s.kind = flattened(points, fit, idle_w, s.plateau_w, rule) ? SaturationKind::saturated
           : late                                            ? SaturationKind::frame_limited
                                                             : SaturationKind::still_rising;
  if (s.kind == SaturationKind::still_rising) return s;
  // Within twice the noise of the plateau a step cannot be told from it: where the noise is
  // wider than the last 5 % of the rise, that is the threshold.
  const double target =
      std::min(idle_w + rule.plateau_share * rise, s.plateau_w - 2.0 * noise_about(points, fit, idle_w, rise));
  const auto crossing = std::find_if(fit.power_w.begin(), fit.power_w.end(), [&](double p) { return p >= target; });
  const std::size_t i = static_cast<std::size_t>(crossing - fit.power_w.begin());
  if (i == 0) {
    s.kind = SaturationKind::saturated_at_start;
    s.count = fit.count.front();
  } else if (i < fit.count.size()) {
    // Linear in the count: below the knee a paced frame's power rises with its busy share,
    // which is proportional to the count.
    const double share = (target - fit.power_w[i - 1]) / (fit.power_w[i] - fit.power_w[i - 1]);
    s.count = fit.count[i - 1] + share * (fit.count[i] - fit.count[i - 1]);
  }  // else the median plateau is above every fitted value: saturated at the last count
  return s;
}

CalibrationResult calibrate_profile(const CalibrationMeasurements& measured, const SaturationRule& rule) {
  CalibrationResult r;
  const std::pair<const char*, const SweepMeasurement*> sweeps[3] = {
      {"batches", &measured.batches}, {"vertices", &measured.vertices}, {"fragments", &measured.fragments}};
  // Without an idle step (never the case unless interrupted at once), rises count from the
  // lowest first step.
  double baseline = measured.idle_w;
  if (std::isfinite(measured.idle_w))
    r.profile.p_min_w = measured.idle_w;
  else
    r.defaults.push_back("p_min_w");
  if (!std::isfinite(baseline)) {
    for (const auto& [name, sweep] : sweeps) {
      const MonotoneCurve fit = monotone_fit(sweep->points);
      if (!fit.power_w.empty() && !(fit.power_w.front() >= baseline)) baseline = fit.power_w.front();
    }
  }
  double top = baseline;
  for (const auto& [name, sweep] : sweeps) {
    const double plateau = plateau_power(sweep->points);
    if (plateau > top) {
      top = plateau;
      r.p_max_from = name;
    }
  }
  if (!r.p_max_from.empty())
    r.profile.p_max_w = top;
  else
    r.defaults.push_back("p_max_w");
  const double range = top - baseline;
  Saturation* results[3] = {&r.batches, &r.vertices, &r.fragments};
  double* fields[3] = {&r.profile.saturation_batches, &r.profile.saturation_vertices, &r.profile.saturation_fragments};
  for (int i = 0; i < 3; ++i) {
    const auto& [name, sweep] = sweeps[i];
    *results[i] = find_saturation(sweep->points, baseline, range, rule);
    const SaturationKind kind = results[i]->kind;
    const bool measured_count = kind == SaturationKind::saturated || kind == SaturationKind::saturated_at_start ||
                                kind == SaturationKind::frame_limited ||
                                (sweep->complete && kind != SaturationKind::no_data);
    if (measured_count)
      *fields[i] = results[i]->count;
    else
      r.defaults.push_back(std::string("saturation.") + name);
  }
  return r;
}

}  // namespace glbudget::analysis
