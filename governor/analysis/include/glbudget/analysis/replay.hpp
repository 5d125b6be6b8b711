#pragma once
// Replays a frame log through the run-time power model exactly as the governor would run it
// (predict each frame with the coefficients available at that moment, then feed it to the
// online fitter) and through the Vatjus-Anttila baseline (fitted once on the first window),
// and reports both models' errors on the same frames:
//   fitted    frames of configurations the last fit had frames of;
//   reused    frames of other configurations, predicted by reusing the coefficients (§5.4);
//   switch    what the governor's selection relies on: before each configuration change, the
//             power of the next configuration predicted from the counts of the frames still
//             drawn in the old one, against what the next one then measured;
// each per frame and as sliding averages over `average_frames` frames of one configuration
// (the paper reports power averaged over 30 frames). A noise floor comes with them: the error
// of predicting every frame by the mean power of its configuration's run, which no model of a
// frame's counts can beat by much when the sensor's frame-to-frame scatter dominates.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "glbudget/analysis/frame_log.hpp"
#include "glbudget/model/online_fitter.hpp"
#include "glbudget/analysis/prediction_error.hpp"
#include "glbudget/model/reuse.hpp"
#include "glbudget/model/run_time_model.hpp"
#include "glbudget/model/pass_names.hpp"
#include "glbudget/model/variant_table.hpp"

namespace glbudget::analysis {

struct ReplayOptions {
  std::size_t average_frames = 30;  // sliding average length for the averaged errors
  // Frames on each side of a configuration change for the switch error: more average out
  // the sensor's scatter, fewer keep the view on both sides alike.
  std::size_t switch_frames = 5;
  std::size_t settle_frames = 1;   // frames after a change not counted as its measurement
  model::HistorySettings history;  // the fit over several configurations (off: the paper's)
};

struct ReplayErrors {
  PredictionError per_frame, averaged;
};

// A frame both models predicted.
struct ReplayFrame {
  std::uint64_t frame = 0;   // as logged
  std::size_t run = 0;       // configuration run it belongs to
  bool fitted_here = false;  // the model had frames of its configuration
  double measured = 0.0, ours = 0.0, baseline = 0.0;
};

// Means over one configuration run's scored frames.
struct ReplayRun {
  model::Configuration configuration;
  std::size_t scored_frames = 0;
  bool fitted_here = false;  // some of its frames were in the fitted configuration
  double measured_w = 0.0, ours_w = 0.0, baseline_w = 0.0;
};

// One configuration change: the next run's power as predicted in the last frames before it, and
// as it then measured.
struct ReplaySwitch {
  std::size_t to_run = 0;
  double ours_w = 0.0, baseline_w = 0.0, unchanged_w = 0.0, measured_w = 0.0;
};

struct ReplayReport {
  ReplayErrors ours_fitted, ours_reused, baseline_fitted, baseline_reused;
  // Every scored frame, as the system runs (fitting, reusing, refitting): with 30-frame
  // averages, the measure of the paper's figures.
  ReplayErrors ours_all, baseline_all;
  PredictionError ours_switch, baseline_switch;  // one pair per configuration change
  // The reference a model must beat at a switch: the next configuration "draws what this one
  // measured" (its last frames' mean power).
  PredictionError unchanged_switch;
  ReplayErrors floor;  // configuration-run means, all scored frames
  std::vector<ReplayRun> runs;
  std::vector<ReplaySwitch> switches;
  std::vector<ReplayFrame> scored;
  std::size_t frames = 0;
  std::size_t frames_unusable = 0;  // no power or unmeasured counts
  std::size_t configuration_runs = 0;
  std::size_t fits = 0;
  std::size_t history_fits = 0;  // of those, fits over several configurations
  std::size_t checks_failed = 0;
  model::ReuseCoefficients reuse;  // after the last fit
  model::PowerModel model;         // after the last fit, at the levels of its configuration
  model::PassNames names;          // of the model's passes
  model::Configuration model_configuration;
};

ReplayReport replay_frames(const std::vector<LoggedFrame>& frames, const model::PlatformProfile& profile,
                           const model::VariantTable& variants, const model::FitSettings& settings = {},
                           const ReplayOptions& options = {});

}  // namespace glbudget::analysis
