#include "glbudget/model/run_time_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "glbudget/model/fragment_scales.hpp"
#include "glbudget/model/platform_costs.hpp"
#include "glbudget/model/power_curve.hpp"

namespace glbudget::model {

RunTimeModel::RunTimeModel(PlatformProfile profile, ConfigurationSpace space, FitSettings fit, HistorySettings history)
    : space_(std::move(space)), history_settings_(history), fitter_(profile, fit), model_(profile) {
  if (profile.costs) reuse_ = {profile.costs->instruction, profile.costs->texel};
  known_scales_ = FragmentScales(space_);
}

// Before the first fit, the window's prior is the platform's costs (when the profile has
// them) for every pass drawn so far at its level; passes it has not seen yet are left to the
// window fit's pooled prior.
void RunTimeModel::seed_prior(const FrameSample& frame, const Configuration& configuration) {
  const PlatformProfile& profile = model_.profile();
  if (!profile.costs) return;
  PowerModel prior = fitter_.model();
  const PowerModel costs = prior_model(profile, *profile.costs, space_, configuration, frame.passes);
  for (PassIndex pass = 0; pass < costs.coefficients().size(); ++pass)
    if (const PassCoefficients* k = costs.find(pass)) prior.set(pass, *k);
  fitter_.adopt(prior);
}

double RunTimeModel::predict_frame(const FrameSample& frame, const Configuration& configuration) {
  if (!current_.empty() && configuration != current_) fitter_.configuration_changed();
  current_ = configuration;
  if (!predictor_) return std::numeric_limits<double>::quiet_NaN();
  predictor_->set_frame(frame.passes, configuration);
  // A configuration outside the space: its counts were taken as the fitted configuration's.
  return predictor_->predict(space_.contains(configuration) ? configuration : fitted_configuration_);
}

double RunTimeModel::predict(const Configuration& configuration) const {
  if (!predictor_ || !space_.contains(configuration)) return std::numeric_limits<double>::quiet_NaN();
  return predictor_->predict(configuration);
}

void RunTimeModel::predict_all(std::vector<double>& out) const {
  if (predictor_)
    predictor_->predict_all(out);
  else
    out.assign(space_.size(), std::numeric_limits<double>::quiet_NaN());
}

const ConfigurationPredictor* RunTimeModel::predictor_for(const FrameSample& frame,
                                                          const Configuration& configuration) const {
  if (!predictor_) return nullptr;
  scratch_ = *predictor_;
  scratch_->set_frame(frame.passes, space_.contains(configuration) ? configuration : fitted_configuration_);
  return &*scratch_;
}

// The history's coefficients explain several configurations over the last few hundred frames;
// the power of the configuration being drawn may have drifted since (a sensor's slow drift, a
// machine's speed, a scene's lighting). Shifting the per-frame load by the mean residual of
// the fitting window keeps what the history learned about the differences between
// configurations and predicts the current one as the window measured it, as the paper's
// window fit does. The shift may make the per-frame load negative: it is a correction, not a
// cost of its own.
void RunTimeModel::anchor_to_recent(PowerModel& model, const Configuration& configuration) const {
  const std::size_t window = fitter_.last_fit().samples_used;
  double residual = 0.0;
  std::size_t n = 0;
  const std::span<const ConfiguredSample> recent = recent_history();
  for (auto it = recent.rbegin(); it != recent.rend() && n < window; ++it) {
    if (it->configuration != configuration) break;
    residual += linearise_power(model.profile(), it->sample.power_w).alpha - model.alpha(it->sample.passes);
    ++n;
  }
  if (n > 0) model.set_frame_alpha(model.frame_alpha() + residual / static_cast<double>(n));
}

void RunTimeModel::refresh_fragment_scales() {
  if (!predictor_ || !history_settings_.enabled) return;
  known_scales_ = measure_fragment_scales(recent_history(), space_, kMinScaleFrames, &known_scales_);
  predictor_->set_fragment_scales(known_scales_);
}

std::span<const ConfiguredSample> RunTimeModel::recent_history() const {
  const std::size_t kept = std::min(history_.size(), history_settings_.frames);
  return std::span<const ConfiguredSample>(history_).last(kept);
}

void RunTimeModel::remember(const FrameSample& frame, const Configuration& configuration) {
  if (history_settings_.remembered_frames == 0) return;
  Remembered& r = remembered_[configuration];
  const double weight = 1.0 / static_cast<double>(std::min(++r.frames, history_settings_.remembered_frames));
  const auto blend = [weight](double& mean, double value) { mean += weight * (value - mean); };
  blend(r.mean.power_w, frame.power_w);
  // A pass this frame did not draw drew nothing in it.
  for (PassFrame& mean : r.mean.passes) {
    const auto drawn =
        std::find_if(frame.passes.begin(), frame.passes.end(), [&](const PassFrame& p) { return p.pass == mean.pass; });
    const PassCounts counts = drawn == frame.passes.end() ? PassCounts{} : drawn->counts;
    blend(mean.counts.batches, counts.batches);
    blend(mean.counts.vertices, counts.vertices);
    blend(mean.counts.fragments, counts.fragments);
  }
  for (const PassFrame& p : frame.passes) {
    const auto known = std::find_if(r.mean.passes.begin(), r.mean.passes.end(),
                                    [&](const PassFrame& mean) { return mean.pass == p.pass; });
    if (known != r.mean.passes.end()) continue;
    r.mean.passes.push_back(
        {p.pass, {weight * p.counts.batches, weight * p.counts.vertices, weight * p.counts.fragments}});
  }
}

std::span<const ConfiguredSample> RunTimeModel::history_to_fit() {
  const std::span<const ConfiguredSample> recent = recent_history();
  std::set<Configuration> held;
  for (const ConfiguredSample& s : recent) held.insert(s.configuration);
  fit_samples_.clear();
  for (const auto& [configuration, r] : remembered_) {
    if (held.count(configuration)) continue;
    if (fit_samples_.empty()) fit_samples_.assign(recent.begin(), recent.end());
    const std::size_t copies = std::min(r.frames, history_settings_.remembered_frames);
    for (std::size_t i = 0; i < copies; ++i) fit_samples_.push_back({r.mean, configuration});
  }
  if (fit_samples_.empty()) return recent;
  return fit_samples_;
}

OnlineFitter::Event RunTimeModel::learn(const FrameSample& frame, const Configuration& configuration,
                                        double predicted_w) {
  if (is_usable(frame) && space_.contains(configuration)) {
    history_.push_back({frame, configuration});
    remember(frame, configuration);
    if (history_.size() > 2 * history_settings_.frames) {
      history_.erase(history_.begin(), history_.end() - static_cast<std::ptrdiff_t>(history_settings_.frames));
    }
  }
  if (!predictor_ && is_usable(frame)) seed_prior(frame, configuration);
  const OnlineFitter::Event event = fitter_.add_frame(frame, predicted_w);
  if (event != OnlineFitter::Event::Fitted) return event;

  // The paper: the window's coefficients, chi and psi from them.
  PowerModel model = fitter_.model();
  // The window's regression explains the whole load by its passes (the paper's model): a
  // per-frame load adopted from an earlier fit over several configurations is not part of it.
  model.set_frame_alpha(0.0);
  Configuration fitted_at = configuration;
  // The paper solves chi and psi from the one configuration's coefficients. A profile's
  // calibrated costs are a better guess than one window's coefficients, which a slow camera
  // leaves unable to tell the passes apart: they are kept until a fit over several
  // configurations (on the demo's logs this took Sponza's 30-frame error from 5.6 % to 3.2 %).
  if (!model_.profile().costs) reuse_ = solve_reuse(model, space_, configuration, fitter_.last_window_mean(), reuse_);
  fitted_configurations_ = {configuration};
  // Beyond it: with several configurations in the history, one fit over all of them.
  if (history_settings_.enabled) {
    std::set<Configuration> seen;
    const std::span<const ConfiguredSample> samples = history_to_fit();
    for (const ConfiguredSample& s : samples) seen.insert(s.configuration);
    if (seen.size() > 1) {
      if (auto fit = fit_history(samples, space_, model, configuration, reuse_, configuration, history_settings_.fit)) {
        model = fit->model;
        reuse_ = fit->reuse;
        anchor_to_recent(model, configuration);
        fitted_configurations_ = seen;
        fitter_.adopt(model);
        ++history_fits_;
      }
    }
  }
  fitted_configuration_ = fitted_at;
  model_ = model;
  if (predictor_)
    predictor_->refit(model, fitted_at, reuse_);
  else
    predictor_.emplace(space_, model, fitted_at, reuse_);
  // Beyond the paper, with the history: fragments at every render-scale or shadow-map level
  // seen in it as measured, not as the table's declared areas (fragment_scales.hpp).
  refresh_fragment_scales();
  return event;
}

}  // namespace glbudget::model
