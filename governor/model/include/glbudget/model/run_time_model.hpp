#pragma once
// The power model as the governor runs it, frame by frame: predict the frame (and any other
// configuration) from the coefficients of the moment, then learn from it. Wraps the paper's
// online fitter (§5.3, §5.5: fitting and accuracy-check windows) and reuse (§5.4), and,
// beyond the paper, refits over the recent frames of every configuration seen once there is
// more than one (history_fit.hpp).
#include <cstddef>
#include <map>
#include <optional>
#include <set>
#include <span>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/history_fit.hpp"
#include "glbudget/model/online_fitter.hpp"
#include "glbudget/model/reuse.hpp"

namespace glbudget::model {

struct HistorySettings {
  bool enabled = true;
  std::size_t frames = 300;  // usable frames kept, newest last
  // Beyond the history: a configuration whose frames have all left it is remembered by the mean
  // of its last frames (their counts and power, an exponential average over this many), and
  // enters every history fit as this many frames. Without it, once the app's best
  // configuration had been left for 300 frames no frame said what its levels cost: on the
  // demo's Subway at 60 %, drawn at a quarter of its fragments since, a refit predicted the best
  // at 28.5 W where it had measured 40 W, and a configuration near it, predicted 25 W, drew
  // 38-40 W (docs/evaluation/budgets.md, run D). 0: forgotten.
  std::size_t remembered_frames = 30;
  HistoryFitSettings fit;
};

class RunTimeModel {
 public:
  RunTimeModel(PlatformProfile profile, ConfigurationSpace space, FitSettings fit = {}, HistorySettings history = {});

  // Sets the frame (its counts, drawn in `configuration`) and returns the predicted power of
  // that configuration; NaN before the first fit.
  double predict_frame(const FrameSample& frame, const Configuration& configuration);
  // Another configuration for the frame last given to predict_frame().
  double predict(const Configuration& configuration) const;
  void predict_all(std::vector<double>& out) const;
  // The coefficients of the moment for another frame's counts (drawn in `configuration`),
  // leaving the current frame as it is: a scratch copy of the predictor, valid until the next
  // call; null before the first fit.
  const ConfigurationPredictor* predictor_for(const FrameSample& frame, const Configuration& configuration) const;
  // Beyond a fit: the fragments measured at every render-scale or shadow-map level the history
  // holds replace the declared ones now (fragment_scales.hpp), so that a level drawn since the
  // last fit predicts the others from what it was measured to draw.
  void refresh_fragment_scales();

  // Learns from the frame last predicted (call after predict_frame, with its prediction).
  OnlineFitter::Event learn(const FrameSample& frame, const Configuration& configuration, double predicted_w);

  bool fitted() const { return predictor_.has_value(); }
  // The last fit saw frames drawn in this configuration.
  bool has_data_for(const Configuration& configuration) const {
    return fitted_configurations_.count(configuration) > 0;
  }
  std::size_t fits() const { return fitter_.fits(); }
  std::size_t history_fits() const { return history_fits_; }
  ReuseCoefficients reuse() const { return reuse_; }
  // The coefficients in use: at the levels of fitted_configuration().
  const PowerModel& model() const { return model_; }
  const Configuration& fitted_configuration() const { return fitted_configuration_; }

 private:
  void seed_prior(const FrameSample& frame, const Configuration& configuration);
  void anchor_to_recent(PowerModel& model, const Configuration& configuration) const;
  // The last HistorySettings::frames usable frames, oldest first.
  std::span<const ConfiguredSample> recent_history() const;
  void remember(const FrameSample& frame, const Configuration& configuration);
  // What a history fit reads: the recent history, then each remembered configuration it no
  // longer holds as remembered_frames copies of its mean (in fit_samples_).
  std::span<const ConfiguredSample> history_to_fit();

  ConfigurationSpace space_;
  HistorySettings history_settings_;
  OnlineFitter fitter_;
  // Kept contiguous so a fit reads it in place; trimmed to `frames` only once it holds twice
  // as many, so a frame costs no shift of the whole history.
  std::vector<ConfiguredSample> history_;
  struct Remembered {
    FrameSample mean;
    std::size_t frames = 0;
  };
  std::map<Configuration, Remembered> remembered_;
  std::vector<ConfiguredSample> fit_samples_;
  PowerModel model_;
  std::optional<ConfigurationPredictor> predictor_;
  mutable std::optional<ConfigurationPredictor> scratch_;  // predictor_for()
  Configuration current_;
  Configuration fitted_configuration_;
  std::set<Configuration> fitted_configurations_;
  ReuseCoefficients reuse_;
  std::size_t history_fits_ = 0;
  // Fragment scales as measured so far: a level the history no longer holds keeps its last
  // measured scale (fragment_scales.hpp).
  FragmentScales known_scales_;
};

}  // namespace glbudget::model
