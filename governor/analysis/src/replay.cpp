#include "glbudget/analysis/replay.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "glbudget/analysis/resolved_frame.hpp"
#include "glbudget/model/run_time_model.hpp"
#include "glbudget/analysis/vatjus_anttila_model.hpp"

namespace glbudget::analysis {

using namespace glbudget::model;
namespace {

using ScoredFrame = ReplayFrame;

// Sliding averages over `length` consecutive scored frames of one run and one class.
void add_sliding_averages(const std::vector<ScoredFrame>& scored, std::size_t length,
                          bool (*in_class)(const ScoredFrame&), double ScoredFrame::*predicted,
                          const std::vector<double>* run_mean, PredictionError& out) {
  std::size_t begin = 0;
  while (begin < scored.size()) {
    std::size_t end = begin;
    while (end < scored.size() && scored[end].run == scored[begin].run &&
           in_class(scored[end]) == in_class(scored[begin])) {
      ++end;
    }
    if (in_class(scored[begin])) {
      for (std::size_t first = begin; first + length <= end; ++first) {
        double predicted_sum = 0.0, measured_sum = 0.0;
        for (std::size_t i = first; i < first + length; ++i) {
          predicted_sum += run_mean ? (*run_mean)[scored[i].run] : scored[i].*predicted;
          measured_sum += scored[i].measured;
        }
        out.add(predicted_sum / static_cast<double>(length), measured_sum / static_cast<double>(length));
      }
    }
    begin = end;
  }
}

bool fitted_class(const ScoredFrame& f) { return f.fitted_here; }
bool reused_class(const ScoredFrame& f) { return !f.fitted_here; }
bool any_class(const ScoredFrame&) { return true; }

}  // namespace

ReplayReport replay_frames(const std::vector<LoggedFrame>& frames, const PlatformProfile& profile,
                           const VariantTable& variants, const FitSettings& settings, const ReplayOptions& options) {
  const double range = profile.range_w();
  ReplayReport report;
  for (ReplayErrors* e : {&report.ours_fitted, &report.ours_reused, &report.baseline_fitted, &report.baseline_reused,
                          &report.ours_all, &report.baseline_all, &report.floor}) {
    *e = {PredictionError(range), PredictionError(range)};
  }
  report.ours_switch = report.baseline_switch = report.unchanged_switch = PredictionError(range);
  report.frames = frames.size();
  report.names = PassNames(variants.space);

  // Resolve every frame first: the runs of one configuration, and which comes next, are
  // known before the replay reaches them (the switch predictions need the next one).
  std::vector<ResolvedFrame> resolved;
  std::vector<std::size_t> run_of;
  std::vector<std::size_t> run_start{0};
  Configuration current(variants.space.pass_count(), 0);
  for (std::size_t t = 0; t < frames.size(); ++t) {
    resolved.push_back(resolve_frame(frames[t], variants, current, report.names));
    if (t > 0 && resolved[t].configuration != current) run_start.push_back(t);
    current = resolved[t].configuration;
    run_of.push_back(run_start.size() - 1);
  }
  run_start.push_back(frames.size());
  report.configuration_runs = frames.empty() ? 0 : run_start.size() - 1;
  const auto run_end = [&](std::size_t run) { return run_start[run + 1]; };

  RunTimeModel model(profile, variants.space, settings, options.history);
  VatjusAnttilaModel baseline(profile);
  std::vector<FrameTotals> baseline_window;
  std::vector<double> baseline_power;
  std::vector<ScoredFrame> scored;
  // Per run: the predictions of the next run's power made during its last frames.
  std::vector<double> switch_ours(report.configuration_runs, 0.0), switch_baseline(report.configuration_runs, 0.0);
  std::vector<double> switch_measured(report.configuration_runs, 0.0);
  std::vector<std::size_t> switch_count(report.configuration_runs, 0);

  for (std::size_t t = 0; t < frames.size(); ++t) {
    const ResolvedFrame& frame = resolved[t];
    if (!is_usable(frame.sample)) {
      ++report.frames_unusable;
      continue;
    }
    const std::size_t run = run_of[t];
    const double predicted = model.predict_frame(frame.sample, frame.configuration);
    const double predicted_baseline = baseline.fitted() ? baseline.predict_power(frame.totals) : std::nan("");
    // Both models are scored on the same frames only.
    if (std::isfinite(predicted) && std::isfinite(predicted_baseline)) {
      scored.push_back({frames[t].frame, run, model.has_data_for(frame.configuration), frame.sample.power_w, predicted,
                        predicted_baseline});
    }
    const bool has_next = run + 1 < report.configuration_runs;
    if (has_next && t + options.switch_frames >= run_end(run) && baseline.fitted() && model.fitted()) {
      const Configuration& next = resolved[run_start[run + 1]].configuration;
      const double ours = model.predict(next);
      const double theirs = baseline.predict_power(totals_in(frame, variants, next));
      if (std::isfinite(ours) && std::isfinite(theirs)) {
        switch_ours[run] += ours;
        switch_baseline[run] += theirs;
        switch_measured[run] += frame.sample.power_w;
        ++switch_count[run];
      }
    }

    if (!baseline.fitted() && std::isfinite(frame.totals.triangles) && std::isfinite(frame.totals.texels)) {
      baseline_window.push_back(frame.totals);
      baseline_power.push_back(frame.sample.power_w);
      if (baseline_window.size() >= settings.fitting_window) baseline.fit(baseline_window, baseline_power);
    }

    const OnlineFitter::Event event = model.learn(frame.sample, frame.configuration, predicted);
    if (event == OnlineFitter::Event::CheckFailed) ++report.checks_failed;
  }
  report.fits = model.fits();
  report.history_fits = model.history_fits();
  report.reuse = model.reuse();
  report.model = model.model();
  report.model_configuration = model.fitted_configuration();

  for (const ScoredFrame& f : scored) {
    (f.fitted_here ? report.ours_fitted : report.ours_reused).per_frame.add(f.ours, f.measured);
    (f.fitted_here ? report.baseline_fitted : report.baseline_reused).per_frame.add(f.baseline, f.measured);
    report.ours_all.per_frame.add(f.ours, f.measured);
    report.baseline_all.per_frame.add(f.baseline, f.measured);
  }
  const std::size_t n = std::max<std::size_t>(1, options.average_frames);
  add_sliding_averages(scored, n, fitted_class, &ScoredFrame::ours, nullptr, report.ours_fitted.averaged);
  add_sliding_averages(scored, n, reused_class, &ScoredFrame::ours, nullptr, report.ours_reused.averaged);
  add_sliding_averages(scored, n, fitted_class, &ScoredFrame::baseline, nullptr, report.baseline_fitted.averaged);
  add_sliding_averages(scored, n, reused_class, &ScoredFrame::baseline, nullptr, report.baseline_reused.averaged);
  add_sliding_averages(scored, n, any_class, &ScoredFrame::ours, nullptr, report.ours_all.averaged);
  add_sliding_averages(scored, n, any_class, &ScoredFrame::baseline, nullptr, report.baseline_all.averaged);

  report.runs.resize(report.configuration_runs);
  for (std::size_t r = 0; r < report.configuration_runs; ++r)
    report.runs[r].configuration = resolved[run_start[r]].configuration;
  for (const ScoredFrame& f : scored) {
    ReplayRun& run = report.runs[f.run];
    ++run.scored_frames;
    run.fitted_here = run.fitted_here || f.fitted_here;
    run.measured_w += f.measured, run.ours_w += f.ours, run.baseline_w += f.baseline;
  }
  for (ReplayRun& run : report.runs) {
    const double n = static_cast<double>(std::max<std::size_t>(1, run.scored_frames));
    run.measured_w /= n, run.ours_w /= n, run.baseline_w /= n;
  }

  // The floor: each scored frame predicted by its run's mean measured power.
  std::vector<double> run_sum(report.configuration_runs, 0.0), run_mean(report.configuration_runs, 0.0);
  std::vector<std::size_t> run_frames(report.configuration_runs, 0);
  for (const ScoredFrame& f : scored) run_sum[f.run] += f.measured, ++run_frames[f.run];
  for (std::size_t r = 0; r < run_mean.size(); ++r) {
    run_mean[r] = run_frames[r] ? run_sum[r] / static_cast<double>(run_frames[r]) : std::nan("");
  }
  for (const ScoredFrame& f : scored) report.floor.per_frame.add(run_mean[f.run], f.measured);
  add_sliding_averages(scored, n, any_class, &ScoredFrame::ours, &run_mean, report.floor.averaged);

  // Switches: the mean prediction made in the old configuration's last frames against the
  // new configuration's measured mean over as many frames, once it has settled.
  for (std::size_t r = 0; r + 1 < report.configuration_runs; ++r) {
    if (switch_count[r] == 0) continue;
    double measured_sum = 0.0;
    std::size_t measured = 0;
    for (std::size_t t = run_start[r + 1] + options.settle_frames;
         t < run_end(r + 1) && measured < options.switch_frames; ++t) {
      if (!is_usable(resolved[t].sample)) continue;
      measured_sum += resolved[t].sample.power_w;
      ++measured;
    }
    if (measured == 0) continue;
    const double count = static_cast<double>(switch_count[r]);
    const ReplaySwitch change{r + 1, switch_ours[r] / count, switch_baseline[r] / count, switch_measured[r] / count,
                              measured_sum / static_cast<double>(measured)};
    report.ours_switch.add(change.ours_w, change.measured_w);
    report.baseline_switch.add(change.baseline_w, change.measured_w);
    report.unchanged_switch.add(change.unchanged_w, change.measured_w);
    report.switches.push_back(change);
  }
  report.scored = std::move(scored);
  return report;
}

}  // namespace glbudget::analysis
