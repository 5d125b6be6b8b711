#include "glbudget/loop/governor.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <sstream>

#include "glbudget/loop/error_selection.hpp"
#include "glbudget/loop/expected_selection.hpp"
#include "glbudget/loop/held_exploration.hpp"
#include "glbudget/model/additive_levels.hpp"
#include "glbudget/model/temporal_filter.hpp"

namespace glbudget::loop {
namespace {

using Clock = std::chrono::steady_clock;

// Of the best's power above P_m, the least saving the model must predict for the cheapest
// configuration to be taken for telling the configurations apart (explore_cheapest, within_band).
constexpr double kUnseenSaving = 0.05;

// The configuration of the space with every pass at its best level: probes shown there draw one
// stream fewer (probe_overhead.hpp).
bool is_best(const model::ConfigurationSpace& space, const model::Configuration& configuration) {
  return space.contains(configuration) &&
         std::all_of(configuration.begin(), configuration.end(), [](int level) { return level == 0; });
}

// The entry of a pass in a frame's (or a window's summed) counts; end() when it drew none.
std::vector<model::PassFrame>::iterator find_pass(std::vector<model::PassFrame>& passes, model::PassIndex pass) {
  return std::find_if(passes.begin(), passes.end(), [pass](const model::PassFrame& p) { return p.pass == pass; });
}

// A level's calibrated change from the best, never above 0: a level below the best that measured
// more than the best did is the calibration's scatter (the cpu estimate's stretches of a few
// seconds reading 2-5 W high put 73 of 216 levels in 18 of the demo's calibrations 0.01-4.6 W
// over the best, some of them in every scene). Taken as measured, such levels cancelled the
// others' savings when summed: Sponza's cheapest was predicted 1.7 W under the best where the
// same calibration measured it 11.7 W under, and the governor took it for dearer than the
// configuration with only resolution and shadows at their cheapest, which drew 19 W against its
// 17.8 W.
double calibrated_change_w(double watts, double best_w) { return std::min(0.0, watts - best_w); }

double microseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::micro>(Clock::now() - start).count();
}

std::string configuration_text(const model::Configuration& configuration) {
  std::string text;
  for (std::size_t i = 0; i < configuration.size(); ++i) {
    text += (i ? "," : "") + std::to_string(configuration[i]);
  }
  return text.empty() ? "(none)" : text;
}

std::string budget_text(const model::Budget& budget) {
  std::ostringstream text;
  if (budget.kind == model::Budget::Kind::ShareOfRange)
    text << budget.value * 100.0 << "%";
  else
    text << budget.value << " W";
  return text.str();
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

}  // namespace

const char* event_name(Event event) {
  switch (event) {
    case Event::none:
      return "none";
    case Event::fit:
      return "fit";
    case Event::check:
      return "check";
    case Event::refit:
      return "refit";
    case Event::select:
      return "select";
    case Event::explore:
      return "explore";
    case Event::transition:
      return "transition";
    case Event::hold:
      return "hold";
  }
  return "none";
}

Governor::Governor(model::PlatformProfile profile, model::ConfigurationSpace space, ErrorTable errors,
                   GovernorSettings settings)
    : space_(std::move(space)),
      errors_(std::move(errors)),
      settings_(settings),
      model_(profile, space_, settings.fit, settings.history),
      p_min_w_(profile.p_min_w),
      feedback_(settings.feedback),
      error_feedback_(settings.error_feedback),
      meter_(settings.feedback.window_s) {
  probe_overhead_.set_keep_share(settings.feedback.keep_share);
  if (!errors_.fits(space_)) {
    notes_.push_back("the error table does not match the configuration space (" + std::to_string(errors_.pass_count()) +
                     " passes for " + std::to_string(space_.pass_count()) + "); using the stand-in errors");
    errors_ = ErrorTable(space_);
  }
  std::optional<double> error_budget = settings_.error_budget;
  if (error_budget && !(std::isfinite(*error_budget) && *error_budget >= 0.0)) {
    std::ostringstream text;
    text << "error budget " << *error_budget << " is not a number >= 0 (1 - SSIM); ignoring it";
    notes_.push_back(text.str());
    error_budget.reset();
  }
  settings_.error_budget = error_budget;

  if (settings_.power.kind != model::Budget::Kind::Off) {
    aim_ = Aim::power;
    if (error_budget) {
      std::ostringstream text;
      text << "both a power budget (" << budget_text(settings_.power) << ") and an error budget (" << *error_budget
           << ") are set: the power budget wins, the error budget is ignored";
      notes_.push_back(text.str());
    }
  } else if (error_budget) {
    aim_ = Aim::error;
  } else {
    notes_.push_back("no power or error budget: observing only, the configuration is never changed");
  }
  governing_ = aim_ != Aim::observe;

  const std::vector<std::string> stand_ins = errors_.stand_in_passes();
  if (!stand_ins.empty()) {
    notes_.push_back("error estimates use a stand-in for passes without measured errors (" + joined(stand_ins) +
                     "): 0.01 at a pass's cheapest level, linear in the level; give their levels an `error` "
                     "in the manifest");
  }
  budget_w_ = initial_budget_w();
  calibrated_levels_ = aim_ == Aim::power && settings_.level_interactions != GovernorSettings::Interactions::model &&
                       settings_.feedback.enabled && settings_.calibrated_range &&
                       std::any_of(settings_.calibrated_powers.begin(), settings_.calibrated_powers.end(),
                                   [](const auto& c) { return model::only_pass_changed(c.first) >= 0; });
  if (settings_.level_interactions == GovernorSettings::Interactions::additive ||
      settings_.level_interactions == GovernorSettings::Interactions::scaled)
    interaction_share_ = 0.0;
  if (settings_.level_interactions == GovernorSettings::Interactions::scaled)
    savings_scale_ = calibrated_savings_scale();
}

// Of each calibrated level's change, the share that puts the cheapest where calibration measured
// it when the changes are summed (LevelInteractions::scaled): (best - cheapest) over the summed
// changes of each pass's last level, never above 1. 1 where a pass's last level was not measured.
double Governor::calibrated_savings_scale() const {
  const auto& range = settings_.calibrated_range;
  if (!range) return 1.0;
  const model::Configuration cheapest = space_.cheapest();
  double summed_saving_w = 0.0;
  std::size_t passes_found = 0;
  for (const auto& [calibrated, watts] : settings_.calibrated_powers) {
    model::Configuration c = calibrated;
    c.resize(space_.pass_count(), 0);
    const int changed = model::only_pass_changed(c);
    if (changed < 0 || c[static_cast<std::size_t>(changed)] != cheapest[static_cast<std::size_t>(changed)]) continue;
    summed_saving_w -= calibrated_change_w(watts, range->best_w);
    ++passes_found;
  }
  const auto passes_cut =
      static_cast<std::size_t>(std::count_if(cheapest.begin(), cheapest.end(), [](int l) { return l > 0; }));
  const double saving_w = range->best_w - range->cheapest_w;
  if (passes_found != passes_cut || !(summed_saving_w > 0.0) || !std::isfinite(saving_w)) return 1.0;
  return std::clamp(saving_w / summed_saving_w, 0.0, 1.0);
}

double Governor::initial_budget_w() const {
  if (aim_ == Aim::power && settings_.power.kind == model::Budget::Kind::Watts) return settings_.power.value;
  if (aim_ == Aim::power) return std::numeric_limits<double>::quiet_NaN();
  return std::numeric_limits<double>::infinity();
}

void Governor::start(const FrameRecord& record) {
  started_ = true;
  last_selection_frame_ = record.frame;
  if (space_.contains(record.configuration)) {
    current_ = record.configuration;
  } else {
    current_ = model::Configuration(space_.pass_count(), 0);
    if (governing_) {
      notes_.push_back("the first frame was drawn in configuration " + configuration_text(record.configuration) +
                       ", outside the space of " + std::to_string(space_.pass_count()) +
                       " passes; starting from the best configuration");
    }
  }
  target_ = current_;
}

// The model sees every frame but probe frames, which drew more than the frame; it learns only
// from frames with power.
model::OnlineFitter::Event Governor::see(const FrameRecord& record, Decision& decision) {
  if (record.probe) return model::OnlineFitter::Event::None;
  sample_.power_w = record.power_w;
  sample_.passes.assign(record.passes.begin(), record.passes.end());
  Clock::time_point start = Clock::now();
  // The model learns from its own prediction; the feedback and the log take the governor's.
  const double model_w = model_.predict_frame(sample_, record.configuration);
  decision.predicted_w = predicted_for_frame(record.configuration, model_w);
  times_.predict_frame.add(microseconds_since(start));
  if (!std::isfinite(record.power_w)) return model::OnlineFitter::Event::None;

  const std::size_t fits_before = model_.fits();
  start = Clock::now();
  const model::OnlineFitter::Event event = model_.learn(sample_, record.configuration, model_w);
  const double us = microseconds_since(start);
  times_.learn.add(us);
  if (model_.fits() != fits_before) {
    if (fits_before == 0) fitted_frame_ = record.frame;
    times_.fit.add(us);
    // The new coefficients take effect from the next frame given to the model: give it this
    // one again, so that a selection now predicts with them (the first fit has no frame yet).
    const double refitted_w =
        predicted_for_frame(record.configuration, model_.predict_frame(sample_, record.configuration));
    if (fits_before > 0 && settings_.feedback.rebase_on_refit) {
      // The residual of the configuration being drawn was measured moments ago, at counts
      // like this frame's: it follows the change of its prediction for this frame, the old
      // coefficients' being the one see() made above (power_feedback.hpp), and this frame
      // joins its window as the new coefficients predict it. Those of the others were
      // measured at other frames, where the change differs: moving them by this frame's
      // accumulates that difference refit after refit (on the synthetic scene of the loop's
      // tests it doubled the prediction error), so they wait for their next window.
      feedback_.rebase(record.configuration, space_.contains(record.configuration)
                                                 ? refitted_w - decision.predicted_w
                                                 : std::numeric_limits<double>::quiet_NaN());
      decision.predicted_w = refitted_w;
    }
  }
  return event;
}

bool Governor::selection_due(const FrameRecord& record) const {
  if (!model_.fitted() || record.probe) return false;
  if (selections_ == 0) {
    // Under a power budget the first selection waits for a window of measured power at the
    // configuration the app starts in (its best, usually), at most select_frames after the
    // fit: that window is what anchors the top of the range (share_of_range_w) and what
    // the corrections of the configurations measured later are told apart from.
    if (aim_ != Aim::power || !feedback_.settings().enabled || feedback_.measured(current_)) return true;
    return record.frame < fitted_frame_ || record.frame - fitted_frame_ >= settings_.select_frames;
  }
  if (reselect_now_) return true;
  if (exploring_) return false;  // until a window at the cheapest configuration is measured
  // Beyond the paper: when the model predicts the chosen configuration over the budget for
  // reselect_over_budget_frames frames in a row (the scene got heavier, or a refit learnt that it costs
  // more), select again at once instead of waiting out select_frames over budget.
  if (settings_.reselect_over_budget_frames > 0 && over_budget_frames_ >= settings_.reselect_over_budget_frames)
    return true;
  // A frame number that went backwards (a new counter) is taken as a due selection.
  return record.frame < last_selection_frame_ || record.frame - last_selection_frame_ >= settings_.select_frames;
}

bool Governor::select(const FrameRecord& record) {
  Clock::time_point start = Clock::now();
  // With the fragment scales this frame's predictions were made with, which predict_all keeps.
  if (aim_ == Aim::power) weigh_at_windows();
  model_.refresh_fragment_scales();
  model_.predict_all(power_);
  times_.predict_all.add(microseconds_since(start));

  start = Clock::now();
  errors_.estimate_all(error_);
  // Under a power budget the selection ranks configurations by their estimates, and what the
  // correction would do to that ranking is not measured; the dual problem holds the estimate
  // itself to the budget.
  if (aim_ == Aim::error) error_feedback_.correct_all(space_, error_);
  times_.estimate_errors.add(microseconds_since(start));

  start = Clock::now();
  margin_w_ = 0.0;
  double budget_w = std::numeric_limits<double>::infinity();
  const std::size_t best = space_.index_of(model::Configuration(space_.pass_count(), 0));
  double best_discount_w = 0.0;  // what the best's weight was lowered by for its cheaper probes
  const bool share = aim_ == Aim::power && settings_.power.kind == model::Budget::Kind::ShareOfRange;
  // 0 % of the range is the cheapest configuration's own prediction (range_ends): no guard for
  // the configurations never measured, which would raise the cheapest over a dearer one measured.
  const bool range_bottom = share && settings_.power.value <= 0.0;
  if (aim_ == Aim::power) {
    model_power_.assign(power_.begin(), power_.end());
    set_calibrated_prior();
    feedback_.correct(space_, power_);
    hold_interactions();
    if (share) range_at_selection_ = range_ends();
    budget_w = share ? share_of_range_w(range_at_selection_) : model::budget_watts(settings_.power, power_);
    // 100 % of the range admits the best configuration by definition: no margin below it.
    const bool whole_range = share && settings_.power.value >= 1.0;
    // Besides the spread's margin and the windows' overshoot, what the quality probes add to
    // the windows: the model's predictions leave them out, the user's meter not.
    const double margin_without_probes_w = feedback_.margin_w() + overshoot_w_;
    // Until a probe shown away from the best is measured, it is taken to draw one frame of the
    // best configuration above idle more than those measured (probe_overhead.hpp).
    if (best < power_.size()) probe_overhead_.set_best_stream_w(power_[best] - p_min_w_);
    probe_margin_w_ = whole_range ? std::numeric_limits<double>::infinity() : probe_window_margin_w();
    best_probe_margin_w_ = probe_window_margin_w(true);
    margin_w_ = whole_range ? 0.0 : margin_without_probes_w + probe_margin_w_;
    guard_unmeasured(whole_range || range_bottom ? 0.0 : feedback_.unmeasured_margin_w(), !whole_range);
    const bool probes_were_rare = probe_period_wanted_ > 0, bursts_were_rare = probe_bursts_spaced_;
    if (!whole_range) {
      want_probe_period(budget_w, margin_without_probes_w);
      // Probes of the other kind from now on (sweeps or probes in turn): their margins.
      const double to_kind = probe_kind_factor();
      probe_margin_w_ *= to_kind;
      best_probe_margin_w_ *= to_kind;
      margin_w_ = margin_without_probes_w + probe_margin_w_;
    }
    // Probes held rare until now and not from this selection on: the share the probes were
    // planned at found their mean, but they come at the shim's own period from now, and each
    // window holding one must fit its whole excess (the demo's Sponza at 50 % with sweeps: a
    // selection kept 0.02 W for the probes as it let them resume, the sweep after it put its
    // window 1-2 W over the budget). The next selection reads the period they came at.
    if (!whole_range &&
        ((probes_were_rare && probe_period_wanted_ == 0) || (bursts_were_rare && !probe_bursts_spaced_))) {
      const double window_s = settings_.feedback.window_s;
      const double to_kind = probe_kind_factor();
      probe_margin_w_ = std::max(probe_margin_w_, to_kind * probe_overhead_.whole_excess_margin_w(window_s));
      best_probe_margin_w_ =
          std::max(best_probe_margin_w_, to_kind * probe_overhead_.whole_excess_margin_w(window_s, true));
      margin_w_ = margin_without_probes_w + probe_margin_w_;
    }
    // The best's own probes draw one stream fewer: it keeps only what they cost. After the
    // probe period is weighed, whose two margins would each need their own lowering.
    if (!whole_range && best < guarded_.size()) {
      best_discount_w = std::max(0.0, probe_margin_w_ - best_probe_margin_w_);
      guarded_[best] -= best_discount_w;
    }
  }
  if (aim_ != Aim::power) guarded_.assign(power_.begin(), power_.end());  // weighed as predicted
  model::Selection selection = aim_ == Aim::power ? model::select_configuration(guarded_, error_, budget_w, margin_w_)
                                                  : select_within_error(power_, error_, *settings_.error_budget);
  // The best's discount holds against budget - margin only. Where nothing fits there, the
  // selection falls back to the configuration of lowest weight, every other one weighed without
  // its margin: the discounted best then looked the cheapest (the demo's Sponza at 40 % with a
  // 22.5 W margin: the best, predicted 37.7 W, weighed 21.2 W and was chosen at every selection
  // for 33 s; docs/evaluation/budgets.md, run C). The fallback weighs it as the others.
  if (aim_ == Aim::power && best_discount_w > 0.0 && !(guarded_[selection.index] <= budget_w - margin_w_)) {
    guarded_[best] += best_discount_w;
    selection = model::select_configuration(guarded_, error_, budget_w, margin_w_);
  }
  if (aim_ == Aim::power && !range_bottom)
    selection = select_at_expected_power(selection, budget_w, feedback_.unmeasured_margin_w());
  times_.select.add(microseconds_since(start));

  ++selections_;
  reselect_now_ = false;
  reselect_after_window_ns_.reset();
  last_selection_frame_ = record.frame;
  chosen_index_ = selection.index;
  budget_w_ = selection.budget_w;
  within_budget_ = selection.within_budget;
  model::Configuration chosen = space_.decode(selection.index);
  const bool explore = aim_ == Aim::power && (explore_cheapest(budget_w) || explore_held(selection, budget_w));
  if (explore) {
    chosen = space_.cheapest();
    chosen_index_ = space_.index_of(chosen);
    exploring_ = explored_ = true;
  }
  if (chosen == target_) return explore;
  // A new target mid-transition starts from where the transition has got to (and a target
  // that is where it has got to ends it).
  transitioning_ = chosen != current_;
  transition_from_ = current_;
  target_ = std::move(chosen);
  transition_start_ns_ = record.time_ns;
  transition_path_ = {};
  // Under a power budget the steps that save come first; under an error budget, whose selection
  // holds the estimated error, the steps that lower it (the image's losses last).
  const std::vector<double>& order_by = aim_ == Aim::error ? error_ : guarded_;
  if (transitioning_ && settings_.ordered_transition)
    transition_path_ = model::ordered_transition(transition_from_, target_, [&](const model::Configuration& c) {
      const std::size_t i = space_.contains(c) ? space_.index_of(c) : order_by.size();
      return i < order_by.size() ? order_by[i] : std::numeric_limits<double>::quiet_NaN();
    });
  return explore;
}

// Beyond the paper: the corrected predictions as the selection weighs them, each configuration
// never measured in the run raised by extra_w (PowerFeedback::unmeasured_margin_w). On the
// demo's Sponza a configuration differing from the best in one level was predicted 7 W under
// what its first window measured: the additive correction cannot see a level whose saving
// depends on the others'. Measured ones are held to what their windows showed.
// Before the first surprise, no window has shown how far such predictions miss: each
// unmeasured configuration is raised by first_saving_discount of its predicted saving below the
// configuration measured (the one the run started in), instead (power_feedback.hpp).
void Governor::guard_unmeasured(double extra_w, bool discount_first) {
  guarded_.assign(power_.begin(), power_.end());
  const FeedbackSettings& feedback = feedback_.settings();
  const std::vector<model::Configuration> measured = feedback_.measured_configurations();
  measured_.assign(guarded_.size(), false);
  for (const model::Configuration& c : measured)
    if (space_.contains(c) && space_.index_of(c) < measured_.size()) measured_[space_.index_of(c)] = true;
  double reference_w = std::numeric_limits<double>::quiet_NaN();
  if (discount_first && feedback.enabled && feedback.guard_unmeasured && feedback.first_saving_discount > 0.0 &&
      feedback_.surprises() == 0) {
    const model::Configuration& reference = measured.empty() ? current_ : measured.front();
    if (space_.contains(reference)) reference_w = power_[space_.index_of(reference)];
  }
  // Under 1, so that the configurations keep their order and one cheaper than the measured fits.
  const double discount = std::clamp(feedback.first_saving_discount, 0.0, 0.9);
  for (std::size_t i = 0; i < guarded_.size(); ++i) {
    if (extra_w > 0.0) guarded_[i] += extra_w;
    if (std::isfinite(reference_w) && std::isfinite(power_[i]))
      guarded_[i] += discount * std::max(0.0, reference_w - power_[i]);
  }
  for (std::size_t i = 0; i < guarded_.size(); ++i)
    if (measured_[i]) guarded_[i] = measured_weighed_w(i);
}

// The guard less the typical surprise, for select_at_expected_power (expected_selection.hpp),
// over the configurations guard_unmeasured found measured.
model::Selection Governor::select_at_expected_power(const model::Selection& guarded, double budget_w, double extra_w) {
  return loop::select_at_expected_power(guarded, guarded_, measured_, error_, budget_w, margin_w_,
                                        extra_w - feedback_.typical_surprise_w());
}

// Beyond the paper. A model fitted on the frames of one configuration whose counts barely
// vary may put the whole load on terms no knob changes: on glmark2's terrain with no manifest
// and the hand-made profile, every configuration was once predicted at the same 23.2 W while
// the window at 60 % measured 19.7 W. Such a model keeps choosing the best configuration, and
// the windows measured there can never show it wrong. So once per run, when the model predicts
// the cheapest configuration (every pass at its last level) to save under kUnseenSaving of the
// best's power above P_m, and the budget asks for less than the best (a share under 100 %, or
// watts the best is predicted over), the cheapest is drawn for one feedback window: its
// measurement anchors the low end of the range (share_of_range_w), and its frames teach the
// history fit what the knobs save.
bool Governor::explore_cheapest(double budget_w) const {
  if (explored_ || !feedback_.settings().enabled || space_.size() < 2) return false;
  const model::Configuration cheapest = space_.cheapest();
  if (feedback_.measured(cheapest)) return false;
  const model::Configuration best(space_.pass_count(), 0);
  const std::size_t b = space_.index_of(best), c = space_.index_of(cheapest);
  const double best_w = best_now_w();
  if (!std::isfinite(best_w) || !std::isfinite(model_power_[c]) || !(best_w > p_min_w_)) return false;
  const bool asks_less =
      settings_.power.kind == model::Budget::Kind::ShareOfRange ? settings_.power.value < 1.0 : power_[b] > budget_w;
  return asks_less && model_power_[b] - model_power_[c] < kUnseenSaving * (best_w - p_min_w_);
}

// Held over the budget at a measured configuration where the range says the cheapest draws
// less: the cheapest is drawn for one window, once per run (held_exploration.hpp).
bool Governor::explore_held(const model::Selection& selection, double budget_w) const {
  if (explored_ || !settings_.explore_when_held || !feedback_.settings().enabled || space_.size() < 2) return false;
  if (feedback_.measured(space_.cheapest()) || selection.index >= power_.size()) return false;
  // The probes as the pick's windows hold them: the margin the selection kept for them (a
  // probe's whole excess where most windows hold one), the best's own at the best.
  const double probes_w = is_best(space_, space_.decode(selection.index)) ? best_probe_margin_w_ : probe_margin_w_;
  const HeldSelection held{selection.index, guarded_, power_, &measured_, budget_w, margin_w_, probes_w};
  return explore_where_held(held, range_ends().low_w, feedback_.margin_w());
}

// The calibration's watts above P_m to the run's: the best's power now above P_m over the
// calibrated best's; NaN without a calibrated range, or when either is not above P_m.
double Governor::calibrated_scale(double best_now_w) const {
  const auto& range = settings_.calibrated_range;
  if (!range || !(range->best_w > p_min_w_) || !std::isfinite(best_now_w) || !(best_now_w > p_min_w_))
    return std::numeric_limits<double>::quiet_NaN();
  return (best_now_w - p_min_w_) / (range->best_w - p_min_w_);
}

// The cheapest configuration as calibration measured it, scaled to the best's power now: a
// share, so that a scene lighter or heavier than the calibration's, or a sensor that drifted
// since, moves both ends together. NaN without a calibrated range.
double Governor::calibrated_cheapest_w(double best_now_w) const {
  const double k = calibrated_scale(best_now_w);
  if (!std::isfinite(k)) return std::numeric_limits<double>::quiet_NaN();
  const auto& range = *settings_.calibrated_range;
  return p_min_w_ + k * std::clamp(range.cheapest_w - p_min_w_, 0.0, range.best_w - p_min_w_);
}

// A share of the range in watts. Beyond the paper: the range runs from the cheapest
// configuration to the best-quality one, each at the model's prediction moved by its own
// measured residual where it has one (the app starts at its best), the cheapest's else by the
// best's, the best's within GovernorSettings::best_band of its windows (best_now_w); with a
// calibrated range (`glbudget calibrate --app` measured the best and the
// cheapest, every pass at its last level) the cheapest is the best's power above P_m times
// the share the calibration measured, unless the run has measured it itself. A correction
// learnt at another configuration (a level whose saving the model misjudged) moves every
// corrected prediction drawing that level, the cheapest's too; a range over corrected
// predictions follows it away from what the app draws, and the budget with it.
Governor::RangeEnds Governor::range_ends() const {
  RangeEnds ends;
  const std::size_t top = model::range_top(model_power_, error_);
  if (top >= power_.size()) return ends;
  ends.top = top;
  const double high = is_best(space_, space_.decode(top)) ? best_now_w() : measured_now_w(top);
  const double shift = high - model_power_[top];
  double low = std::numeric_limits<double>::infinity();
  const model::Configuration last_levels = space_.cheapest();
  if (feedback_.measured(last_levels)) {
    low = within_band(settings_.measured_at_windows ? measured_now_w(space_.index_of(last_levels))
                                                    : power_[space_.index_of(last_levels)],
                      cheapest_windows_);
  } else {
    low = calibrated_cheapest_w(high);
  }
  if (!std::isfinite(low)) {
    std::size_t cheapest = top;
    for (std::size_t i = 0; i < model_power_.size(); ++i)
      if (model_power_[i] < model_power_[cheapest]) cheapest = i;
    const model::Configuration c = space_.decode(cheapest);
    low = feedback_.measured(c) ? measured_now_w(cheapest) : model_power_[cheapest] + shift;
  }
  ends.low_w = low;
  ends.high_w = high;
  return ends;
}

double Governor::share_of_range_w(const RangeEnds& ends) const {
  if (ends.top >= power_.size()) return std::numeric_limits<double>::infinity();
  const double low = ends.low_w, high = ends.high_w;
  const std::size_t top = ends.top;
  const double share = settings_.power.value;
  // 0 % admits exactly the configuration the selection takes for the cheapest, 100 % the best
  // as the selection sees it, measured or not.
  if (share <= 0.0) {
    // Measured configurations as guard_unmeasured weighs them (at their windows' power where
    // measured_at_windows found it).
    double cheapest_w = low;
    for (std::size_t i = 0; i < power_.size(); ++i) cheapest_w = std::min(cheapest_w, measured_weighed_w(i));
    return cheapest_w;
  }
  if (share >= 1.0) return std::max(high, power_[top]);
  return (1.0 - share) * std::min(low, high) + share * high;
}

// Beyond the paper: `glbudget calibrate --app` measured the best configuration and each level
// alone; a level's measured difference from the best, scaled to the best's power now above
// P_m, less the difference the model predicts for this frame, is what the model misjudges of
// that level (on the demo's Sponza: a shadow map 4x smaller saves 5 W measured, and the model,
// which sees no fragment-shader work in a depth-only pass, predicts nothing). It is the
// feedback's prior for the level, until windows measured in the run say otherwise.
void Governor::set_calibrated_prior() {
  const auto& measured = settings_.calibrated_powers;
  const auto& range = settings_.calibrated_range;
  if (measured.empty() || !range || !feedback_.settings().enabled) return;
  const model::Configuration best(space_.pass_count(), 0);
  const std::size_t best_index = space_.index_of(best);
  const double scale = calibrated_scale(best_now_w());
  if (!std::isfinite(scale)) return;
  std::vector<std::vector<double>> prior(space_.pass_count());
  for (const auto& [calibrated, watts] : measured) {
    model::Configuration c = calibrated;
    c.resize(space_.pass_count(), 0);
    const int changed = model::only_pass_changed(c);
    if (changed < 0 || !space_.contains(c)) continue;  // the best, the cheapest: not one level alone
    const std::size_t pass = static_cast<std::size_t>(changed);
    const std::size_t level = static_cast<std::size_t>(c[pass]);
    const double predicted = model_power_[space_.index_of(c)] - model_power_[best_index];
    if (!std::isfinite(predicted)) continue;
    if (prior[pass].size() <= level) prior[pass].resize(level + 1, 0.0);
    prior[pass][level] = scale * savings_scale_ * calibrated_change_w(watts, range->best_w) - predicted;
  }
  feedback_.set_prior(std::move(prior));
}

void Governor::hold(const FrameRecord& record) {
  if (holding_) return;
  holding_ = true;
  transitioning_ = false;
  target_ = current_;
  transition_path_ = {};
  if (hold_noted_) return;
  hold_noted_ = true;
  notes_.push_back("no power measurement for " + std::to_string(missing_power_) + " frames (frame " +
                   std::to_string(record.frame) + "): holding configuration " + configuration_text(current_) +
                   " until power returns");
}

// Windows of measured power at the settled target correct its prediction; one measured over
// the budget asks for a selection at once. The frame's prediction is given corrected.
void Governor::feed_back(const FrameRecord& record, Decision& decision) {
  if (record.probe || !space_.contains(record.configuration)) return;
  const bool settled = settled_at_target(record.configuration);
  std::optional<PowerFeedback::Window> window;
  if (!settled) {
    feedback_.interrupt();
  } else {
    const std::uint64_t taken = feedback_.frames_taken(), opened = feedback_.windows_opened();
    window = feedback_.add(record.configuration, record.time_ns, record.power_w, decision.predicted_w);
    count_window_frame(record, feedback_.frames_taken() != taken, feedback_.windows_opened() != opened, window);
  }
  if (window && is_best(space_, record.configuration))
    best_windows_.add(window->measured_w, settings_.feedback.memory_windows);
  if (window && record.configuration == space_.cheapest())
    cheapest_windows_.add(window->measured_w, settings_.feedback.memory_windows);
  if (window) {
    if (exploring_) {
      // The cheapest is measured: select again with it, and leave the overshoot out of it.
      exploring_ = false;
      reselect_now_ = true;
    } else if (std::isfinite(budget_w_) && selections_ > 0) {
      // The window as the user's meter sees it: its frames and the probes drawn among them.
      const double measured_w = window->measured_w + probe_overhead_.watts(is_best(space_, record.configuration));
      if (measured_w > budget_w_) reselect_now_ = true;
      // Beyond the paper: windows over the budget accumulate, and windows under it pay back,
      // what the next selection keeps under the budget besides the spread's margin (integral
      // control). Where the model misjudges the savings of configurations not yet drawn, the
      // corrections learnt one configuration at a time converge slowly; this does not wait
      // for them. Never negative: it never admits more than the predictions do.
      overshoot_w_ = std::clamp(overshoot_w_ + (measured_w - budget_w_), 0.0, std::max(0.0, budget_w_ - p_min_w_));
    }
  }
  if (std::isfinite(decision.predicted_w)) decision.predicted_w += feedback_.bias(record.configuration);
}

void Governor::meter(const FrameRecord& frame) {
  if (!settings_.meter_windows) return;
  const bool settled =
      settled_at_target(frame.configuration) && std::isfinite(budget_w_) && selections_ > 0 && !exploring_;
  if (!settled) {
    meter_.interrupt();
    return;
  }
  const std::optional<MeterWindow::Reading> window = meter_.add(frame.time_ns, frame.power_w, frame.probe);
  if (!window || !window->measured() || !(window->watts > budget_w_)) return;
  // A window holding a probe is over the budget by design where the last selection kept only
  // the probes' mean under it (probes rare enough that few windows hold one; ProbeOverhead's
  // window_margin_w): selecting again would find the same. Where it kept a probe's whole excess,
  // or the window holds none, the configuration draws more than the selection counted on.
  constexpr double kPlannedShare = 0.9;
  const bool probe_planned_for =
      probe_margin_w_ >= kPlannedShare * probe_overhead_.whole_excess_margin_w(settings_.feedback.window_s);
  if (!(window->probes == 0 || probe_planned_for)) return;
  // The meter's window holding a probe closes at the probe frame, while the feedback's leaves
  // the probe and the two frames after it out and closes a few frames later. Selecting at once
  // left the configuration unmeasured, and the selection counted on the same prediction that
  // had just put the window over (the demo's Sponza at 40 and 50 %: the first configuration,
  // predicted 19.2 W, drew 23.7 W; the next one chosen, its neighbour predicted 20.3 W, drew
  // 25.3 W, and four windows went over). The selection waits for the feedback's window, once
  // (a later meter's window over the budget does not put the wait off).
  if (window->probes > 0 && feedback_.window_open_at(frame.configuration)) {
    if (!reselect_after_window_ns_) reselect_after_window_ns_ = frame.time_ns;
  } else {
    reselect_now_ = true;
  }
}

void Governor::watch_budget(const FrameRecord& frame) {
  const double budget_w = aim_ == Aim::power && selections_ > 0 ? budget_w_ : std::numeric_limits<double>::quiet_NaN();
  const std::optional<BudgetWatch::Verdict> v = budget_watch_.add(frame.time_ns, frame.power_w, budget_w);
  if (!v) return;
  std::ostringstream text;
  text << std::fixed << std::setprecision(1) << "the power budget is not being kept: " << v->over << " of the last "
       << v->of << " s measured over it (" << v->measured_w << " W against " << v->budget_w << " W) at "
       << std::setprecision(0) << v->frames_per_s << " frames a second. ";
  // Frames drawn as fast as they can be turn what a cheaper configuration saves into more
  // frames at the same power. Those paced come within a few percent of the pace.
  constexpr double kBehindPace = 0.9;
  if (!(settings_.paced_fps > 0.0))
    text << "glbudget does not pace these frames (no --fps, GLBUDGET_FPS): an app that draws as fast as it can "
            "turns a cheaper configuration into more frames at the same power, not less power; give --fps N, the "
            "frame rate to keep";
  else if (v->frames_per_s < kBehindPace * settings_.paced_fps)
    text << "The frames do not keep up with the pace asked for (" << settings_.paced_fps
         << " a second): drawn as fast as they can be, a cheaper configuration turns into more frames at the same "
            "power, not less power; give a lower --fps, or draw a smaller window";
  else
    text << "The configurations drawn do not reach it: raise the budget, or give the manifest cheaper levels";
  notes_.push_back(text.str());
}

// Counts of frames with non-finite counts are not summed; their window's mean is then not kept.
void Governor::count_window_frame(const FrameRecord& record, bool taken, bool new_window,
                                  const std::optional<PowerFeedback::Window>& closed) {
  if (!settings_.measured_at_windows || !taken) return;
  if (new_window) {
    open_counts_.sum.clear();
    open_counts_.frames = 0;
  }
  const bool finite = std::all_of(record.passes.begin(), record.passes.end(), [](const model::PassFrame& p) {
    return std::isfinite(p.counts.batches) && std::isfinite(p.counts.vertices) && std::isfinite(p.counts.fragments);
  });
  if (finite) {
    for (const model::PassFrame& pass : record.passes) {
      auto it = find_pass(open_counts_.sum, pass.pass);
      if (it == open_counts_.sum.end()) it = open_counts_.sum.insert(it, model::PassFrame{pass.pass, {}});
      it->counts.batches += pass.counts.batches;
      it->counts.vertices += pass.counts.vertices;
      it->counts.fragments += pass.counts.fragments;
    }
    ++open_counts_.frames;
  }
  if (!closed) return;
  const bool whole = open_counts_.frames == closed->frames;
  const auto n = static_cast<double>(open_counts_.frames);
  open_counts_.frames = 0;
  if (!whole) return;
  // The window's means join the configuration's as its residual's memory weighs them.
  WindowCounts& counts = window_counts_[record.configuration];
  ++counts.windows;
  const double weight = memory_weight(counts.windows, settings_.feedback.memory_windows);
  const auto blend = [weight](double& mean, double value) { mean += weight * (value - mean); };
  std::vector<model::PassFrame>& mean = counts.mean.passes;
  for (model::PassFrame& pass : mean) {  // passes this window did not draw drew nothing in it
    if (find_pass(open_counts_.sum, pass.pass) != open_counts_.sum.end()) continue;
    blend(pass.counts.batches, 0.0);
    blend(pass.counts.vertices, 0.0);
    blend(pass.counts.fragments, 0.0);
  }
  for (const model::PassFrame& sum : open_counts_.sum) {
    auto it = find_pass(mean, sum.pass);
    if (it == mean.end()) it = mean.insert(mean.end(), model::PassFrame{sum.pass, {}});
    blend(it->counts.batches, sum.counts.batches / n);
    blend(it->counts.vertices, sum.counts.vertices / n);
    blend(it->counts.fragments, sum.counts.fragments / n);
  }
  blend(counts.mean.power_w, closed->measured_w);
}

// Beyond the paper: a residual is what a window measured less what the coefficients of its time
// predicted. The configuration being drawn has its residual moved at each refit (see()); the
// others keep the old coefficients' error, and their corrected predictions move with every
// refit's extrapolation: on the demo's Subway at 60 %, the best, measured in the run's first
// seconds and the top of the range, was corrected to 38.9 W, then 28.3 W after one refit, then
// 41.0 W, while the configuration drawn measured 22-24 W throughout, and the budget fell 8.6 W
// for 80 frames. Predicted now and at its windows' counts by the same coefficients and fragment
// scales (those of this frame's predictions: select() calls this before refreshing them), the
// difference is what they say the scene's counts changed since, and what was measured stays.
void Governor::weigh_at_windows() {
  measured_now_.assign(space_.size(), std::numeric_limits<double>::quiet_NaN());
  if (!settings_.measured_at_windows) return;
  for (const auto& [c, counts] : window_counts_) {
    if (!space_.contains(c) || !feedback_.measured(c)) continue;
    // The model holds this frame (see() gave it), predicted with the scales still in force.
    const double now_w = model_.predict(c);
    const model::ConfigurationPredictor* at_windows = model_.predictor_for(counts.mean, c);
    const double then_w = at_windows ? at_windows->predict(c) : std::numeric_limits<double>::quiet_NaN();
    const double moved_w = counts.mean.power_w + (now_w - then_w);
    if (std::isfinite(moved_w)) measured_now_[space_.index_of(c)] = moved_w;
  }
}

double Governor::measured_weighed_w(std::size_t index) const {
  return index < measured_now_.size() && std::isfinite(measured_now_[index]) ? measured_now_[index] : power_[index];
}

void Governor::EndWindows::add(double measured_w, double memory_windows) {
  ++windows;
  mean_w += memory_weight(windows, memory_windows) * (measured_w - mean_w);
}

// Where the model cannot tell the configurations apart (it predicts the cheapest to save under
// kUnseenSaving of the best's measured power above P_m), the ends follow its predictions: held
// to what they measured, the range would leave every prediction outside it (a knob the model
// does not see; "a model that cannot tell the configurations apart", governor_loop_test).
double Governor::within_band(double now_w, const EndWindows& end) const {
  const double band = settings_.best_band;
  if (end.windows == 0 || !(band >= 0.0) || std::isinf(band) || !std::isfinite(now_w)) return now_w;
  const std::size_t b = space_.index_of(model::Configuration(space_.pass_count(), 0));
  const std::size_t c = space_.index_of(space_.cheapest());
  if (best_windows_.windows == 0 || std::max(b, c) >= model_power_.size() ||
      !(model_power_[b] - model_power_[c] >= kUnseenSaving * (best_windows_.mean_w - p_min_w_)))
    return now_w;
  // Measured under P_m (a profile whose idle was measured high), the band is as wide as its
  // distance from it.
  const double width_w = band * std::abs(end.mean_w - p_min_w_);
  return std::clamp(now_w, end.mean_w - width_w, end.mean_w + width_w);
}

double Governor::best_now_w() const {
  return within_band(measured_now_w(space_.index_of(model::Configuration(space_.pass_count(), 0))), best_windows_);
}

double Governor::measured_now_w(std::size_t index) const {
  if (index < measured_now_.size() && std::isfinite(measured_now_[index])) return measured_now_[index];
  return model_power_[index] + feedback_.residual(space_.decode(index));
}

// Beyond the paper: probes came more often than the last selection planned for (a burst: a
// probe found the scene moved, and every pass is probed again), so that each window may now
// hold one's whole excess where the selection kept only their mean under the budget. Selecting
// again at once keeps the burst's windows in the budget, instead of waiting for windows
// measured over it.
bool Governor::probes_outgrew_margin() const {
  if (aim_ != Aim::power || selections_ == 0 || !std::isfinite(probe_margin_w_)) return false;
  constexpr double kRise = 0.25;  // of a probe's whole excess in a window: not the excess's own drift
  return probe_window_margin_w() >
         probe_margin_w_ + kRise * probe_overhead_.whole_excess_margin_w(settings_.feedback.window_s);
}

double Governor::probe_window_margin_w(bool shown_best) const {
  return probe_overhead_.window_margin_w(settings_.feedback.window_s, settings_.feedback.keep_share, shown_best);
}

double Governor::probe_kind_factor(int streams) const { return probe_overhead_.kind_factor(streams); }

double Governor::probe_kind_factor() const { return probe_streams_fit_ ? probe_kind_factor(probe_streams_fit_) : 1.0; }

// Probes rare enough that windows keep their mean margin, where the selection would then show
// a lower error by probe_stretch_gain, or where no configuration is predicted to fit a probe's
// whole excess under the budget but some would fit rare probes' mean (a narrow range at a low
// share: every window with a probe would be over it, whatever is drawn, and reselecting cannot
// help); then a burst of probes (the scene moved) is spaced so too. The shim's own period
// where that gain is under half of it and a probe's excess fits (a gap between the two
// thresholds keeps the period from flapping with the noise).
void Governor::want_probe_period(double budget_w, double margin_without_probes_w) {
  const double gap = probe_overhead_.rare_gap(settings_.feedback.window_s, settings_.feedback.keep_share);
  // probe_stretch_gain 0: the shim's probes as it plans them, their kind too.
  if (!(settings_.probe_stretch_gain > 0.0) || gap <= 0.0 || probe_overhead_.probes_measured() == 0) {
    probe_period_wanted_ = 0;
    probe_bursts_spaced_ = false;
    return;
  }
  double whole = probe_overhead_.whole_excess_margin_w(settings_.feedback.window_s);
  double rare = probe_overhead_.watts_at_gap(gap);
  const double scatter_w = feedback_.margin_w();
  const auto fits = [&](double margin_w) {
    return std::any_of(guarded_.begin(), guarded_.end(), [&](double p) { return p <= budget_w - margin_w; });
  };
  // Where sweeps were asked for, the probes' kind (probe_streams_fit), weighed at its excess.
  if (sweepable_streams_ > kOnePassStreams) {
    const double one_pass = probe_kind_factor(kOnePassStreams);
    const auto shown_error = [&](int streams) {
      const double margin_w = margin_without_probes_w + whole * probe_kind_factor(streams);
      return error_[model::select_configuration(guarded_, error_, budget_w, margin_w).index];
    };
    if (!fits(scatter_w + whole * one_pass)) {
      probe_streams_fit_ = sweepable_streams_;
    } else {
      probe_streams_fit_ = kOnePassStreams;
      const double one_pass_error = shown_error(kOnePassStreams);
      for (int streams = sweepable_streams_; streams > kOnePassStreams; --streams) {
        if (fits(scatter_w + whole * probe_kind_factor(streams)) &&
            shown_error(streams) <= one_pass_error + settings_.sweep_image_cost) {
          probe_streams_fit_ = streams;
          break;
        }
      }
    }
    const double to_kind = probe_kind_factor();
    whole *= to_kind;
    rare *= to_kind;
  }
  const model::Selection with_whole =
      model::select_configuration(guarded_, error_, budget_w, margin_without_probes_w + whole);
  const model::Selection with_rare =
      model::select_configuration(guarded_, error_, budget_w, margin_without_probes_w + rare);
  const double gain = error_[with_whole.index] - error_[with_rare.index];
  // The probes' whole excess is what leaves no room beside the sensor's scatter (where nothing
  // fits without it either, the predictions put every window over the budget, probes or not,
  // and rarer probes would only leave the estimates staler). The windows' overshoot is left
  // out: where probes leave no room, the windows they put over the budget are what run it up.
  const bool probes_leave_no_room = !fits(scatter_w + whole) && fits(scatter_w + rare);
  probe_bursts_spaced_ = probes_leave_no_room;
  if (probes_leave_no_room || gain >= settings_.probe_stretch_gain)
    probe_period_wanted_ = static_cast<std::uint64_t>(gap);
  else if (gain < 0.5 * settings_.probe_stretch_gain)
    probe_period_wanted_ = 0;
}

Decision Governor::on_frame(const FrameRecord& frame) {
  if (!started_) start(frame);
  probe_overhead_.set_period_in_force(frame.probe_period);
  probe_overhead_.set_sweep_streams(frame.sweeping_streams);
  sweepable_streams_ = frame.sweepable_streams;
  probe_overhead_.add(frame.probe, frame.power_w, frame.time_ns, is_best(space_, frame.configuration),
                      frame.probe_sweep_streams);
  // The frame after a probe reads the probe's images back and compares them, and the one after
  // that still finishes some of its work: part of their power is the probe's (counted by
  // probe_overhead_), so neither the model nor the feedback takes it for their configuration's;
  // each is seen as a frame without power.
  const bool after_probe = !frame.probe && probe_overhead_.in_span();
  if (after_probe) {
    after_probe_record_ = frame;
    after_probe_record_.power_w = std::numeric_limits<double>::quiet_NaN();
  }
  const FrameRecord& record = after_probe ? after_probe_record_ : frame;
  Decision decision;
  const model::OnlineFitter::Event learnt = see(record, decision);
  switch (learnt) {
    case model::OnlineFitter::Event::Fitted:
      decision.event = model_.fits() == 1 ? Event::fit : Event::refit;
      break;
    case model::OnlineFitter::Event::CheckPassed:
    case model::OnlineFitter::Event::CheckFailed:
      decision.event = Event::check;
      break;
    default:
      break;
  }

  // A probe's power is not the frame's own: it neither counts as missing nor as back.
  if (!record.probe && !after_probe) missing_power_ = std::isfinite(record.power_w) ? 0 : missing_power_ + 1;
  if (missing_power_ > 0 && missing_power_ >= settings_.hold_after_missing_power) {
    hold(record);
    decision.event = Event::hold;
  } else {
    holding_ = false;
  }

  if (!governing_) {
    decision.next = record.configuration;
    decision.budget_w = budget_w_;
    decision.est_error = estimated_error(record.configuration);
    return decision;
  }

  meter(frame);
  watch_budget(frame);
  if (!holding_) {
    feed_back(record, decision);
    const bool over = !record.probe && settled_at_target(record.configuration) && std::isfinite(budget_w_) &&
                      decision.predicted_w > budget_w_;
    if (!record.probe) over_budget_frames_ = over ? over_budget_frames_ + 1 : 0;
    if (probes_outgrew_margin()) reselect_now_ = true;
    // The wait ends once the feedback's window has closed (feed_back, above), or did not close
    // within a window of the meter's finding it over (frames without power).
    if (reselect_after_window_ns_ &&
        (!feedback_.window_open_at(record.configuration) ||
         static_cast<double>(record.time_ns - *reselect_after_window_ns_) * 1e-9 >= settings_.feedback.window_s)) {
      reselect_after_window_ns_.reset();
      reselect_now_ = true;
    }
    if (selection_due(record)) {
      decision.event = select(record) ? Event::explore : Event::select;
      over_budget_frames_ = 0;
    }
    if (transitioning_) {
      const double t = static_cast<double>(record.time_ns - transition_start_ns_) * 1e-9;
      current_ = transition_path_.configurations.empty()
                     ? model::blend_configurations(transition_from_, target_, t, settings_.transition_s)
                     : model::along_path(transition_path_, t, settings_.transition_s);
      if (!(t < settings_.transition_s)) {
        current_ = target_;
        transitioning_ = false;
        transition_path_ = {};
      }
      if (decision.event == Event::none) decision.event = Event::transition;
    }
  }
  decision.next = current_;
  decision.budget_w = budget_w_;
  // Of the frame's own configuration, as predicted_w is: the row it goes to shows that one, and
  // `next` reaches the screen only frames later (the governor decides behind the render thread).
  decision.est_error = estimated_error(record.configuration);
  decision.within_budget = within_budget_;
  return decision;
}

double Governor::predicted_for_frame(const model::Configuration& configuration, double model_w) const {
  // All of the model's interaction kept: its own prediction, without summing the levels'.
  if (!calibrated_levels_ || interaction_share_ == 1.0 || !space_.contains(configuration)) return model_w;
  const double summed =
      model::additive_over_levels(configuration, [&](const model::Configuration& c) { return model_.predict(c); });
  return summed + interaction_share_ * (model_w - summed);
}

// The corrected predictions (power_), each its levels' changes summed plus the share of the
// model's interaction that the calibrated cheapest calls for (additive_levels.hpp). The
// feedback's correction is additive over levels, so the interaction is the model's alone.
// Once the run has measured the cheapest itself, the share stays where it was: the cheapest's
// correction then holds its windows, interaction included.
void Governor::hold_interactions() {
  if (!calibrated_levels_) return;
  summed_.assign(power_.begin(), power_.end());
  model::make_additive_over_levels(space_, summed_);
  const model::Configuration cheapest = space_.cheapest();
  if (settings_.level_interactions == GovernorSettings::Interactions::calibrated && !feedback_.measured(cheapest)) {
    const double low = calibrated_cheapest_w(power_[space_.index_of(model::Configuration(space_.pass_count(), 0))]);
    const std::size_t c = space_.index_of(cheapest);
    if (std::isfinite(low)) interaction_share_ = model::interaction_share(power_[c] - summed_[c], low - summed_[c]);
  }
  for (std::size_t i = 0; i < power_.size(); ++i)
    power_[i] = summed_[i] + interaction_share_ * (power_[i] - summed_[i]);
}

double Governor::estimated_error(const model::Configuration& configuration) const {
  const double estimate = errors_.estimate(configuration);
  return aim_ == Aim::error ? error_feedback_.correct(configuration, estimate) : estimate;
}

// A probe frame's measurement of what is shown, against the estimate the table now makes of
// it. Under an error budget, one over the budget at the settled target selects again at once
// rather than showing it until the next selection is due.
void Governor::shown_error(const model::Configuration& shown, double measured) {
  if (!space_.contains(shown)) return;
  error_feedback_.add(shown, errors_.estimate(shown), measured);
  if (aim_ == Aim::error && error_feedback_.settings().enabled && selections_ > 0 && !transitioning_ &&
      shown == target_ && measured > *settings_.error_budget)
    reselect_now_ = true;
}

}  // namespace glbudget::loop
