#pragma once
// The governor's decision loop (paper §6): frame by frame, the run-time power model predicts
// and learns; once it is fitted, and then every select_frames frames, every configuration's
// power is predicted and its error estimated, the best one under the budget is selected, and
// the temporal filter moves the rendered configuration there over transition_s.
//
// No GL, no threads, no I/O: the shim calls on_frame() on its governor thread with each frame
// record and applies Decision::next from the next frame on. What the user should know once
// (a stand-in error table, conflicting budgets, a hold) is appended to notes().
#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "glbudget/loop/budget_watch.hpp"
#include "glbudget/loop/error_feedback.hpp"
#include "glbudget/loop/error_table.hpp"
#include "glbudget/loop/level_interactions.hpp"
#include "glbudget/loop/meter_window.hpp"
#include "glbudget/loop/power_feedback.hpp"
#include "glbudget/loop/probe_overhead.hpp"
#include "glbudget/loop/step_times.hpp"
#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/online_fitter.hpp"
#include "glbudget/model/platform_profile.hpp"
#include "glbudget/model/power_model.hpp"
#include "glbudget/model/run_time_model.hpp"
#include "glbudget/model/selection.hpp"
#include "glbudget/model/temporal_filter.hpp"
#include "glbudget/model/variant_table.hpp"

namespace glbudget::loop {

struct GovernorSettings {
  model::Budget power;                 // GLBUDGET_POWER; Off: none
  std::optional<double> error_budget;  // GLBUDGET_ERROR (1 - SSIM); the power budget wins
  std::size_t select_frames = 200;     // frames between selections (paper §6.3)
  double transition_s = 2.0;           // the temporal filter's T (paper §6.2)
  // Beyond the paper: the filter's one-level steps, at the blend's moments, ordered by the power
  // the selection weighed, savings first (under an error budget by the estimated error, its
  // reductions first; model::ordered_transition); false: the paper's blend.
  bool ordered_transition = true;
  std::size_t hold_after_missing_power = 30;  // consecutive frames without power before holding
  // Beyond the paper: select again at once after this many frames in a row whose chosen
  // configuration the model predicts over the budget (0: only every select_frames).
  std::size_t reselect_over_budget_frames = 10;
  // Beyond the paper: each configuration's measured power corrects its prediction, a margin
  // from the measured spread keeps windows within a power budget, and a window measured
  // over the budget selects again at once (power_feedback.hpp).
  FeedbackSettings feedback = {};
  // Beyond the paper: under an error budget, the error each probe frame measured of the
  // configuration shown corrects the estimates (error_feedback.hpp), and one measured over
  // the budget selects again at once.
  ErrorFeedbackSettings error_feedback = {};
  // Beyond the paper: the power `glbudget calibrate --app` measured at the best and the
  // cheapest configuration (the variant table's "power"). A share of the range then takes
  // the cheapest's saving from them rather than from the model, which has seen the cheapest
  // drawn only if the run went there (share_of_range_w).
  std::optional<model::VariantTable::MeasuredRange> calibrated_range;
  // And every configuration it measured (each level alone): what the model misjudges of a
  // level's saving, against what was measured, is the feedback's prior for that level
  // (Governor::calibrated_prior). In the space's pass order; passes beyond them at level 0.
  std::vector<std::pair<model::Configuration, double>> calibrated_powers;
  // How a combination of levels is predicted where calibrated_powers holds levels alone and
  // calibrated_range the cheapest (under a power budget with the feedback on, whose priors
  // hold each single-level prediction to them; model/additive_levels.hpp;
  // level_interactions.hpp).
  using Interactions = LevelInteractions;
  Interactions level_interactions = Interactions::scaled;
  // Beyond the paper: where more windows hold a quality probe than the budget may leave over,
  // each must fit a probe's whole excess (probe_overhead.hpp), and at low frame rates that
  // margin costs the shown image quality. When a selection with the mean margin of probes
  // rare enough (ProbeOverhead::rare_gap: about 40 s apart for a 95 % share) would show an
  // estimated error this much lower, the governor asks for probes that rare
  // (probe_period_wanted); below half of it, it asks for the shim's own period again. The
  // price is staler estimates: every pass probed a few minutes apart, sooner when a probe
  // finds the scene changed; so only for a gain beyond the selection regret the estimates
  // are held to (0.005, issue 14; on Hall, whose errors change along its path, the stale
  // estimates of a 0.002 threshold cost more than the margin gave back). It asks for them
  // whatever the gain where no configuration fits a probe's whole excess beside the sensor's
  // scatter but some fit rare probes' mean, bursts included (probe_bursts_spaced). 0: never.
  double probe_stretch_gain = 0.005;
  // Beyond the paper, where sweeps were asked for (FrameRecord::sweepable_streams): a probe frame
  // measuring more passes at once keeps the estimates fresher, but a window holding it needs more
  // margin, which shows a dearer image. It measures as many as fit where the selection with that
  // margin shows an estimated error at most this much above the one with a probe of one pass's
  // (Governor::probe_streams_fit): fresher estimates are worth the selection regret they are held
  // to (0.005, issue 14), not more (the demo's Hall at 60 %: sweeps' margin showed 0.051 of true
  // error where probes in turn showed 0.032).
  double sweep_image_cost = 0.005;
  // Beyond the paper: where the selection finds nothing within the budget's margin and holds a
  // measured configuration whose windows, probes included, are over the budget, while the
  // range's low end says the cheapest draws less, the cheapest is drawn for one window, once per
  // run (Governor::explore_held). false: the run stays where it is held.
  bool explore_when_held = true;
  // Beyond the paper: a configuration measured in the run is weighed by the selection, and taken
  // for an end of a share's range, at what its windows measured, moved by what the coefficients
  // of the moment predict between those windows' counts and this frame's
  // (Governor::weigh_at_windows). false: the selection weighs it at its prediction now plus the
  // feedback's additive correction, and the range's ends take its own residual, both measured
  // against the coefficients of the windows' time.
  bool measured_at_windows = false;
  // Beyond the paper: the settled configuration's frames are also read as a power meter reads
  // them, in windows of the feedback's length holding every frame, probes and the frames that
  // finish them included (MeterWindow); one over the budget selects again at once. false: a
  // window selects again when its frames without probes plus the probes' mean are over.
  bool meter_windows = true;
  // Beyond the paper: the best configuration's power now, the top of a share's range, stays
  // within this share of what its own windows measured above P_m; its prediction moves it no
  // further. The app starts at its best and leaves it at the first selection, and once the
  // best's frames have left the model's history (300 frames) no frame determines what its
  // levels cost: on the demo's Hall at 60 % the top read 31.2, 22.0 and 39.0 W at three
  // selections while the best drew 33 W, and the budget moved from 24.7 to 16.9 to 29.3 W
  // with it (run ZQ). Over the 709 selections of seven evaluations the top was off the best's
  // power in another run of the same frames by 2.4 W on average and 21 W at worst; held within
  // 0.1 of its measured power above P_m, by 1.9 W and 7.7 W; held at it, by 1.9 W and 7.9 W
  // (docs/evaluation/budgets.md, "the range's top held near its measurement"). The band lets
  // the top follow a scene that grows or shrinks the best's power by up to the share; windows
  // measured at the best again move its centre. Infinite: no bound.
  double best_band = 0.1;
  // The frame rate the shim paces the app's frames to (GLBUDGET_FPS); 0: not paced by the shim.
  // When a power budget is not kept (BudgetWatch), the note says whether frames drawn as fast
  // as they can be may be why: none paced, or too slow for the pace.
  double paced_fps = 60.0;
  model::FitSettings fit = {};
  model::HistorySettings history = {};
};

struct FrameRecord {
  std::uint64_t frame = 0;
  std::int64_t time_ns = 0;                                   // any monotonic clock: only differences are used
  double power_w = std::numeric_limits<double>::quiet_NaN();  // NaN: no measurement
  model::Configuration configuration;                         // what drew the frame
  bool probe = false;                                         // a quality-probe frame: its power is not the frame's
  double probe_period = 0.0;                                  // frames between probes the shim plans now; 0: not known
  // The streams a settled probe frame draws where the shim now measures every pass at once
  // (GLBUDGET_PROBE_SWEEP: the best and one a pass); 0: probes of one pass each.
  int sweeping_streams = 0;
  // On a probe frame: the streams it drew where it measured every pass at once (0: one pass).
  int probe_sweep_streams = 0;
  // Where the user asked for sweeps (GLBUDGET_PROBE_SWEEP), the streams a sweep would draw,
  // whether or not the shim sweeps now (Governor::probe_streams_fit); 0: no sweeps asked for.
  int sweepable_streams = 0;
  // Counts per pass, by its index in the space (PassIndex); passes past the space add a fixed load.
  std::vector<model::PassFrame> passes;
};

// What happened at a frame; when several did, the first in this order: hold, select or explore,
// refit, fit, check, transition.
enum class Event {
  none,
  fit,         // the model's first fit
  check,       // an accuracy check ended (passed or failed)
  refit,       // a later fit (a failed check, or a new configuration's window)
  select,      // a selection ran
  explore,     // a selection ran and, the model unable to tell the configurations apart, chose
               // to measure the cheapest once (Governor::explore_cheapest)
  transition,  // the temporal filter moved towards the selected configuration
  hold,        // power has been missing too long: the configuration is held
};
const char* event_name(Event event);  // "none", "fit", ...

struct Decision {
  model::Configuration next;  // what to draw from the next frame on
  Event event = Event::none;
  // The frame's own predicted power, corrected by what was measured of its configuration
  // (power_feedback.hpp): NaN before the first fit.
  double predicted_w = std::numeric_limits<double>::quiet_NaN();
  // The last selection's power limit; +inf without a power budget, and before the first
  // selection the budget's watts (NaN for a share of the range, which needs predictions).
  double budget_w = std::numeric_limits<double>::infinity();
  double est_error = std::numeric_limits<double>::quiet_NaN();  // the frame's own configuration's estimate
  bool within_budget = true;  // the last selection found a configuration within the budget
};

class Governor {
 public:
  // `errors` must fit `space` (ErrorTable::fits); if it does not, the stand-in table of the
  // space is used instead, with a note.
  Governor(model::PlatformProfile profile, model::ConfigurationSpace space, ErrorTable errors,
           GovernorSettings settings = {});

  Decision on_frame(const FrameRecord& record);

  // Append-only messages for the user, without the "glbudget: " prefix the shim adds.
  const std::vector<std::string>& notes() const { return notes_; }
  const StepTimes& step_times() const { return times_; }

  // Quality probes update the errors through this; the next selection uses them.
  ErrorTable& errors() { return errors_; }
  const ErrorTable& errors() const { return errors_; }
  // A probe frame measured the error of the configuration shown (1 - SSIM against the best
  // configuration's image of the frame); call after the same probe's errors are in errors().
  void shown_error(const model::Configuration& shown, double measured);
  const ErrorFeedback& error_feedback() const { return error_feedback_; }
  const model::RunTimeModel& model() const { return model_; }
  const model::ConfigurationSpace& space() const { return space_; }
  const PowerFeedback& feedback() const { return feedback_; }
  const ProbeOverhead& probe_overhead() const { return probe_overhead_; }
  // Frames between quality probes the governor asks the shim to keep at least, once every
  // pass is probed (GovernorSettings::probe_stretch_gain); 0: the shim's own period.
  std::uint64_t probe_period_wanted() const { return probe_period_wanted_; }
  // Whether the bursts of probes (every pass again when the scene moved) are to keep that
  // period too: no configuration is predicted to fit a probe's whole excess in a window under
  // the budget, so that each window holding a probe would be over it.
  bool probe_bursts_spaced() const { return probe_bursts_spaced_; }
  // Where sweeps were asked for (FrameRecord::sweepable_streams), the most streams a probe frame
  // is to draw: all of them (a sweep: every pass in one probe frame, ahead of each selection)
  // where some configuration is predicted to fit its whole excess in a window under the budget at
  // an image cost of at most GovernorSettings::sweep_image_cost; else the most that do, the passes
  // taken that many at a time at the shim's period for probes in turn (kOnePassStreams: one pass
  // at a time). Where not even a probe of one pass fits, sweeps, which the governor spaces
  // (probe_bursts_spaced): a window holding one is over the budget either way, and a sweep
  // measures every pass. Without this, where a sweep did not
  // fit, the governor spaced them, and the estimates were minutes old where probes in turn kept
  // them within the age bound with every window kept (the demo's Valley at 50 %: not one sweep in
  // 600 frames after the first selection). 0: no sweeps asked for, or probe_stretch_gain 0 (the
  // shim's probes as it plans them).
  int probe_streams_fit() const { return probe_streams_fit_; }
  // The frame the next selection is due at by select_frames (one may come sooner: a window
  // over the budget, a scene that got heavier), for probes that measure just ahead of it;
  // 0 before the first selection, whose frame waits on a measured window.
  std::uint64_t next_selection_frame() const {
    return selections_ > 0 ? last_selection_frame_ + settings_.select_frames : 0;
  }
  // The last selection: every configuration's predicted power (corrected) and estimated
  // error, by ConfigurationSpace index, the power as the selection weighed it (unmeasured
  // configurations raised by the guard, the best lowered by the probes it does not draw), and
  // the margin kept under the budget below that.
  struct SelectionTable {
    std::uint64_t frame = 0;
    std::size_t chosen = 0;
    double budget_w = 0.0;
    double margin_w = 0.0;
    const std::vector<double>* power_w = nullptr;
    const std::vector<double>* error = nullptr;
    const std::vector<double>* weighed_w = nullptr;
    // The ends of a share's range the budget was taken from; infinite under other budgets.
    double range_low_w = std::numeric_limits<double>::infinity();
    double range_high_w = std::numeric_limits<double>::infinity();
    // Of margin_w, what was kept for the quality probes' windows (0 where none was).
    double probe_margin_w = 0.0;
  };
  SelectionTable last_selection() const {
    return {last_selection_frame_,
            chosen_index_,
            budget_w_,
            margin_w_,
            &power_,
            &error_,
            &guarded_,
            range_at_selection_.low_w,
            range_at_selection_.high_w,
            std::isfinite(probe_margin_w_) && margin_w_ > 0.0 ? probe_margin_w_ : 0.0};
  }
  const GovernorSettings& settings() const { return settings_; }
  // The share of the run-time model's interaction between levels the last selection kept
  // (GovernorSettings::level_interactions): 1 where the model's own combination is used.
  double interaction_share() const { return calibrated_levels_ ? interaction_share_ : 1.0; }

  // A power or error budget is in force; false: observe only, nothing is ever changed.
  bool governing() const { return governing_; }
  bool holding() const { return holding_; }
  bool transitioning() const { return transitioning_; }
  // The ordered transition under way: its steps from where it started to the target (empty
  // where the filter blends, and when no transition is under way).
  const model::TransitionPath& transition_path() const { return transition_path_; }
  std::size_t selections() const { return selections_; }
  // The last selection's configuration (before the first: the first frame's).
  const model::Configuration& target() const { return target_; }

 private:
  enum class Aim { observe, power, error };

  void start(const FrameRecord& record);
  model::OnlineFitter::Event see(const FrameRecord& record, Decision& decision);
  bool selection_due(const FrameRecord& record) const;
  // Returns true when it chose to explore instead (explore_cheapest).
  bool select(const FrameRecord& record);
  bool explore_cheapest(double budget_w) const;
  bool explore_held(const model::Selection& selection, double budget_w) const;
  void guard_unmeasured(double extra_w, bool discount_first);
  // Where the guard leaves nothing within the margin: the selection with unmeasured
  // configurations at their expected power (expected_selection.hpp); extra_w: the guard.
  model::Selection select_at_expected_power(const model::Selection& guarded, double budget_w, double extra_w);
  void hold(const FrameRecord& record);
  void feed_back(const FrameRecord& record, Decision& decision);
  // Under a power budget, drawing the target with no transition or hold in the way: what the
  // frame measures is the target's own.
  bool settled_at_target(const model::Configuration& drawn) const {
    return aim_ == Aim::power && !transitioning_ && !holding_ && drawn == target_;
  }
  // The frame as it was measured, probes included, into the meter's window (meter_windows).
  void meter(const FrameRecord& frame);
  // Every frame after the first selection into budget_watch_, which tells once when the budget
  // is not kept.
  void watch_budget(const FrameRecord& frame);
  double initial_budget_w() const;
  void want_probe_period(double budget_w, double margin_without_probes_w);
  // What turns the probes' excess read now into that of probes drawing `streams` streams, and
  // into that of the kind probe_streams_fit asks for (1 before the governor has chosen).
  double probe_kind_factor(int streams) const;
  double probe_kind_factor() const;
  bool probes_outgrew_margin() const;
  // What a selection keeps under the budget for the probes in the feedback's windows
  // (ProbeOverhead::window_margin_w), for probes shown away from the best or at it.
  double probe_window_margin_w(bool shown_best = false) const;
  double calibrated_scale(double best_now_w) const;
  double calibrated_cheapest_w(double best_now_w) const;
  // The range a share of it is taken of: the cheapest's power and the best's (range_top), each
  // as share_of_range_w says; top is past the space where there are no finite predictions.
  struct RangeEnds {
    double low_w = std::numeric_limits<double>::infinity();
    double high_w = std::numeric_limits<double>::infinity();
    std::size_t top = std::numeric_limits<std::size_t>::max();
  };
  RangeEnds range_ends() const;
  double share_of_range_w(const RangeEnds& ends) const;
  double estimated_error(const model::Configuration& configuration) const;
  // The prediction of `configuration` for the frame last given to the model, whose own is
  // model_w, with the levels' interaction as the last selection held it (level_interactions).
  double predicted_for_frame(const model::Configuration& configuration, double model_w) const;
  // The frame just given to the feedback, if it took it (closed: the window it closed), in the
  // counts of its window; a closed window's mean counts and power join its configuration's.
  void count_window_frame(const FrameRecord& record, bool taken, bool new_window,
                          const std::optional<PowerFeedback::Window>& closed);
  // At a selection, with the model holding the selection's frame (measured_at_windows): each
  // measured configuration's power now, what its windows measured moved by the model's
  // prediction at this frame's counts less its prediction at theirs (measured_now_).
  void weigh_at_windows();
  // A measured configuration as the selection weighs it (by space index, after a selection's
  // predictions): as weigh_at_windows found it where it did, else its corrected prediction.
  double measured_weighed_w(std::size_t index) const;
  // A configuration's power now (by space index, after a selection's predictions): as
  // weigh_at_windows found it where it did; else its own prediction plus the residual measured
  // against the coefficients of the windows' time.
  double measured_now_w(std::size_t index) const;
  void hold_interactions();
  void set_calibrated_prior();
  double calibrated_savings_scale() const;
  // The windows' measured power, without probes, of a configuration at an end of the range,
  // averaged as the feedback's residuals are (best_band); windows 0: none measured.
  struct EndWindows {
    double mean_w = 0.0;
    std::size_t windows = 0;
    void add(double measured_w, double memory_windows);
  };
  // `now_w` held within best_band of what `end`'s windows measured above P_m.
  double within_band(double now_w, const EndWindows& end) const;
  // The best configuration's power now (after a selection's predictions): measured_now_w,
  // within best_band of what its windows measured.
  double best_now_w() const;

  model::ConfigurationSpace space_;
  ErrorTable errors_;
  GovernorSettings settings_;
  model::RunTimeModel model_;
  double p_min_w_ = 0.0;  // the profile's P_m
  // GovernorSettings::level_interactions applies (calibrated levels, a power budget, feedback)
  bool calibrated_levels_ = false;
  // Of the model's interaction kept (additive_levels.hpp): 0 for `additive`; for `calibrated`
  // the last selection's, held once the run has measured the cheapest itself.
  double interaction_share_ = 1.0;
  // Under `scaled`, the share of each calibrated level's change its prior takes
  // (calibrated_savings_scale); 1 otherwise.
  double savings_scale_ = 1.0;
  Aim aim_ = Aim::observe;
  bool governing_ = false;

  bool started_ = false;
  model::Configuration current_;  // the last decision's `next`
  EndWindows best_windows_, cheapest_windows_;
  model::Configuration target_;
  model::Configuration transition_from_;
  model::TransitionPath transition_path_;  // ordered_transition, while transitioning_
  std::int64_t transition_start_ns_ = 0;
  bool transitioning_ = false;

  std::size_t selections_ = 0;
  // Consecutive frames whose chosen configuration the model predicts over the budget.
  std::size_t over_budget_frames_ = 0;
  std::uint64_t last_selection_frame_ = 0;
  double budget_w_ = 0.0;
  double margin_w_ = 0.0;
  // What the last selection kept under the budget for the quality probes (infinite: nothing
  // to keep, before a selection or at 100 % of the range).
  double probe_margin_w_ = std::numeric_limits<double>::infinity();
  double best_probe_margin_w_ = 0.0;  // the same for the best's own probes (one stream fewer)
  double overshoot_w_ = 0.0;          // windows' excess over the budget, less what later windows paid back
  std::size_t chosen_index_ = 0;
  bool within_budget_ = true;
  PowerFeedback feedback_;
  ErrorFeedback error_feedback_;
  ProbeOverhead probe_overhead_;
  MeterWindow meter_;
  BudgetWatch budget_watch_;
  std::uint64_t probe_period_wanted_ = 0;
  bool probe_bursts_spaced_ = false;
  int probe_streams_fit_ = 0;
  int sweepable_streams_ = 0;       // FrameRecord::sweepable_streams of the last frame
  FrameRecord after_probe_record_;  // reused: the frame after a probe, its power left out
  bool reselect_now_ = false;       // a window was measured over the budget
  // A meter's window over the budget closed by a probe while the feedback's window at the same
  // configuration is still open: the selection waits for it (meter(), at most a window): the
  // time it was found.
  std::optional<std::int64_t> reselect_after_window_ns_;
  bool exploring_ = false;  // drawing the cheapest configuration until a window measures it
  bool explored_ = false;   // once per run

  std::size_t missing_power_ = 0;
  bool holding_ = false;
  bool hold_noted_ = false;

  model::FrameSample sample_;  // reused: the record as the model sees it
  // The summed counts of the feedback's open window; and each measured configuration's windows:
  // their mean counts and power, averaged as the feedback averages its residual.
  struct OpenCounts {
    std::vector<model::PassFrame> sum;
    std::size_t frames = 0;
  };
  struct WindowCounts {
    model::FrameSample mean;  // power_w: the windows' measured power
    std::size_t windows = 0;
  };
  OpenCounts open_counts_;
  std::map<model::Configuration, WindowCounts> window_counts_;
  std::vector<double> measured_now_;  // by space index; NaN where weigh_at_windows found none
  RangeEnds range_at_selection_;      // the last selection's (share budgets; else both ends infinite)
  std::uint64_t fitted_frame_ = 0;    // the frame of the model's first fit
  std::vector<double> power_;         // reused by selections: corrected predictions
  std::vector<double> model_power_;   // and the model's own
  std::vector<double> guarded_;       // and as the selection weighs them (guard_unmeasured)
  std::vector<bool> measured_;        // and whether each was measured (guard_unmeasured)
  std::vector<double> summed_;        // and as their levels' changes summed (hold_interactions)
  std::vector<double> error_;
  StepTimes times_;
  std::vector<std::string> notes_;
};

}  // namespace glbudget::loop
