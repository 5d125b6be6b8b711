// The governor's decision loop (governor/loop): a synthetic app with a hidden per-pass power
// model (synthetic_scene.hpp) driven in closed loop, frame by frame, through the Governor.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "glbudget/loop/budget_watch.hpp"
#include "glbudget/loop/error_selection.hpp"
#include "glbudget/loop/error_table.hpp"
#include "glbudget/model/variant_table.hpp"
#include "glbudget/loop/from_manifest.hpp"
#include "glbudget/loop/governor.hpp"
#include "glbudget/loop/meter_window.hpp"
#include "glbudget/model/additive_levels.hpp"
#include "glbudget/manifest/manifest.hpp"
#include "glbudget/model/power_curve.hpp"
#include "glbudget/model/temporal_filter.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget;
using namespace glbudget::loop;
using model::Budget;
using model::Configuration;
using model::testing::HiddenModel;
using model::testing::SceneGenerator;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr std::int64_t kFrameNs = 16'666'667;  // 60 fps
constexpr int kFps = 60;
constexpr double kNoiseW = 0.2;  // the sensor's noise (0.5 % of P_M - P_m)
// How far above a budget the truth may be and still count as within it: twice the hidden
// model's noise per frame, sqrt(0.2^2 + 0.27^2) W, the sensor's and that of the frames' 10 %
// jitter in counts (0.27 W measured along the camera path below). A selection sees one frame.
constexpr double kToleranceW = 0.7;
// Frames after which the loop counts as converged: the first fit, selection and transition,
// and the refits that follow it, with room to spare.
constexpr int kConverged = 10 * kFps;

// Errors that do not follow power: passes weigh differently and the middle level of some is
// nearly free, so the search has to trade.
ErrorTable test_errors(const model::ConfigurationSpace& space) {
  ErrorTable table(space);
  const double worst[] = {0.04, 0.02, 0.03, 0.015, 0.008, 0.01};
  const double middle[] = {0.3, 0.5, 0.1, 0.6, 0.4, 0.2};
  for (std::size_t i = 0; i < 6; ++i) {
    REQUIRE(table.set(i, 1, middle[i] * worst[i]));
    REQUIRE(table.set(i, 2, worst[i]));
  }
  return table;
}

// The hidden model's power of every configuration for one frame's counts, from per-pass
// per-level loads (alpha is additive over passes).
struct Truth {
  const HiddenModel& hidden;
  std::vector<std::vector<double>> alpha;  // [pass][level]

  Truth(const HiddenModel& h, const std::vector<model::PassFrame>& frame) : hidden(h) {
    const model::PlatformProfile profile = model::testing::synthetic_profile();
    for (std::size_t i = 0; i < hidden.space.pass_count(); ++i) {
      std::vector<double> levels;
      for (std::size_t l = 0; l < hidden.space.passes()[i].levels.size(); ++l) {
        levels.push_back(model::pass_alpha(profile, hidden.coefficients(i, static_cast<int>(l)), frame[i].counts));
      }
      alpha.push_back(levels);
    }
  }
  double power(const Configuration& c) const {
    double a = 0.0;
    for (std::size_t i = 0; i < alpha.size(); ++i) a += alpha[i][static_cast<std::size_t>(c[i])];
    return model::power_from_alpha(model::testing::synthetic_profile(), a);
  }
  double extreme(bool highest) const {
    double a = 0.0;
    for (const std::vector<double>& levels : alpha) {
      a += highest ? *std::max_element(levels.begin(), levels.end()) : *std::min_element(levels.begin(), levels.end());
    }
    return model::power_from_alpha(model::testing::synthetic_profile(), a);
  }
  // The budget in watts the truth gives for this frame.
  double budget_w(const Budget& budget) const {
    if (budget.kind == Budget::Kind::Watts) return budget.value;
    if (budget.kind == Budget::Kind::Off) return std::numeric_limits<double>::infinity();
    return (1.0 - budget.value) * extreme(false) + budget.value * extreme(true);
  }
};

struct Step {
  FrameRecord record;
  Decision decision;
  double true_power_w = 0.0;
  Configuration target;  // the governor's target after the frame
};

// The app: draws frame k in the configuration of decision k - 1 (the first in `start`), along
// synthetic_scene.hpp's camera path slowed down (the path's counts advance every `slow`
// frames, the 10 % jitter every frame), measured with the sensor's noise. At slow = 64 a
// second's mean power moves by up to 1.2 W in 3 s, slow enough for a selection every 200
// frames to follow; at the path's own speed its power swings by 10 W in 2 s.
class App {
 public:
  // `unseen`: power a configuration draws beyond what the hidden model (and so the counts)
  // explain, e.g. a level whose saving the model misjudges; measured, never predicted.
  App(GovernorSettings settings, Configuration start = Configuration(6, 0), unsigned seed = 7, int slow = 64,
      std::function<double(const Configuration&)> unseen = {})
      : unseen_(std::move(unseen)),
        hidden_(model::testing::six_pass_hidden_model()),
        scene_(hidden_, kNoiseW, seed),
        governor_(model::testing::synthetic_profile(), hidden_.space, test_errors(hidden_.space), settings),
        drawn_(std::move(start)),
        slow_(slow) {}

  // `power` overrides the measured power (NaN: missing); `probe` marks a probe frame, whose
  // counts are those of twice the frame and whose power is `probe_power` times the frame's.
  Step step(std::optional<double> power = std::nullopt, bool probe = false, double probe_power = 2.0) {
    Step s;
    s.record.frame = frame_;
    s.record.time_ns = static_cast<std::int64_t>(frame_) * frame_ns_;
    s.record.configuration = drawn_;
    s.record.probe = probe;
    s.record.probe_period = probe_period_;
    const model::FrameSample sample = scene_.sample(static_cast<int>(frame_) / slow_, drawn_);
    s.record.passes = sample.passes;
    s.record.power_w = power ? *power : sample.power_w;
    s.true_power_w = scene_.true_power(sample.passes, drawn_);
    if (unseen_) {
      s.true_power_w += unseen_(drawn_);
      if (!power) s.record.power_w += unseen_(drawn_);
    }
    s.record.sweepable_streams = sweepable_streams_;
    // Playing the shim: sweeps as the governor last asked (probe_streams_fit), their excess as a
    // probe of one pass's times sweep_excess_factor.
    const int fit = governor_.probe_streams_fit();
    const int streams = sweepable_streams_ > 2 ? (fit > 0 ? std::min(fit, sweepable_streams_) : sweepable_streams_) : 0;
    s.record.sweeping_streams = streams > 2 ? streams : 0;
    if (probe) {
      for (model::PassFrame& p : s.record.passes) p.counts.fragments *= 2.0;
      s.record.power_w *= 1.0 + (probe_power - 1.0) * (streams > 2 ? loop::sweep_excess_factor(streams) : 1.0);
      s.record.probe_sweep_streams = s.record.sweeping_streams;
    }
    s.decision = governor_.on_frame(s.record);
    s.target = governor_.target();
    drawn_ = s.decision.next;
    ++frame_;
    return s;
  }
  std::vector<Step> run(int frames) {
    std::vector<Step> steps;
    for (int k = 0; k < frames; ++k) steps.push_back(step());
    return steps;
  }

  Governor& governor() { return governor_; }
  const HiddenModel& hidden() const { return hidden_; }
  void set_frame_ns(std::int64_t ns) { frame_ns_ = ns; }
  // The probe period the shim would report with the frames from now on (0: not known).
  void set_probe_period(double frames) { probe_period_ = frames; }
  // The streams of a sweep where the shim is asked for sweeps (0: not asked).
  void set_sweepable_streams(int streams) { sweepable_streams_ = streams; }

 private:
  std::function<double(const Configuration&)> unseen_;
  HiddenModel hidden_;
  SceneGenerator scene_;
  Governor governor_;
  Configuration drawn_;
  std::uint64_t frame_ = 0;
  int slow_;
  std::int64_t frame_ns_ = kFrameNs;
  double probe_period_ = 0.0;
  int sweepable_streams_ = 0;
};

GovernorSettings power_budget(const std::string& text) {
  GovernorSettings settings;
  settings.power = *model::parse_budget(text);
  return settings;
}

bool has_note(const Governor& governor, const std::string& part) {
  for (const std::string& note : governor.notes()) {
    if (note.find(part) != std::string::npos) return true;
  }
  return false;
}

// Share of the 1-s windows after convergence in which the selected configuration's mean true
// power is within the mean of the frames' true budgets. (What is drawn during a transition
// passes between the old and the new configuration, and may exceed both: the paper's filter.)
double share_of_windows_within(const App& app, const std::vector<Step>& steps, const Budget& budget) {
  int windows = 0, within = 0;
  for (std::size_t start = kConverged; start + kFps <= steps.size(); start += kFps) {
    double power = 0.0, limit = 0.0;
    for (std::size_t k = start; k < start + kFps; ++k) {
      power += Truth(app.hidden(), steps[k].record.passes).power(steps[k].target);
      limit += Truth(app.hidden(), steps[k].record.passes).budget_w(budget);
    }
    ++windows;
    if (power <= limit + kToleranceW * kFps) ++within;
  }
  return windows ? static_cast<double>(within) / windows : 0.0;
}

// At every selection after convergence: the target's true power is within the budget, and no
// configuration with lower estimated error is safely (by the tolerance) within it too.
void check_selections(const App& app, const Governor& governor, const std::vector<Step>& steps, const Budget& budget) {
  std::vector<double> errors;
  governor.errors().estimate_all(errors);
  int checked = 0;
  for (std::size_t k = kConverged; k < steps.size(); ++k) {
    if (steps[k].decision.event != Event::select) continue;
    ++checked;
    const Truth truth(app.hidden(), steps[k].record.passes);
    const double limit = truth.budget_w(budget);
    const Configuration& chosen = steps[k].target;
    const double chosen_error = governor.errors().estimate(chosen);
    double lowest_safe = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < errors.size(); ++i) {
      if (truth.power(governor.space().decode(i)) <= limit - kToleranceW)
        lowest_safe = std::min(lowest_safe, errors[i]);
    }
    INFO("frame " << k << ": chosen error " << chosen_error << ", power " << truth.power(chosen) << " W, budget "
                  << limit << " W");
    CHECK(truth.power(chosen) <= limit + kToleranceW);
    CHECK(chosen_error <= lowest_safe + 1e-12);
  }
  CHECK(checked >= 5);
}

// Levels changed from one configuration to another, summed over the passes.
int levels_between(const Configuration& a, const Configuration& b) {
  int moved = 0;
  for (std::size_t i = 0; i < a.size(); ++i) moved += std::abs(a[i] - b[i]);
  return moved;
}

// The least weight among the one-level steps from `at` toward `to` (each pass that differs,
// moved one level): what an ordered transition's next step weighs.
double least_next_step(const Configuration& at, const Configuration& to,
                       const std::function<double(const Configuration&)>& weigh) {
  double least = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < at.size(); ++i) {
    if (at[i] == to[i]) continue;
    Configuration step = at;
    step[i] += to[i] > at[i] ? 1 : -1;
    least = std::min(least, weigh(step));
  }
  return least;
}

// How far a selection's table strays from its own levels' changes summed (additive_levels.hpp):
// 0 where every configuration is the best plus its levels' changes alone.
double largest_gap_from_levels_summed(const model::ConfigurationSpace& space, const std::vector<double>& power) {
  double gap = 0.0;
  for (std::size_t index = 0; index < space.size(); ++index) {
    const double sum = model::additive_over_levels(space.decode(index),
                                                   [&](const Configuration& c) { return power[space.index_of(c)]; });
    gap = std::max(gap, std::abs(power[index] - sum));
  }
  return gap;
}

}  // namespace

TEST_CASE("power budgets: within the budget after convergence, at the lowest feasible error", "[loop]") {
  // A share of the range moves with the scene; watts do not, so between two selections (200
  // frames) the scene's drift would add to a watts budget's overshoot, but a refit that finds
  // the chosen configuration over the budget selects again at once: the watts budget keeps
  // up with the same camera speed.
  // The scene's predictions hold, so the selection is held to the lowest error the truth
  // admits with the surprise floor off; the floor's price here is stated with it
  // (power_feedback.hpp, surprise_floor_share), and with it on the windows keep the budget too.
  for (const auto& [text, slow] : {std::pair{"40%", 64}, {"50%", 64}, {"60%", 64}, {"50W", 64}}) {
    INFO("budget " << text);
    GovernorSettings settings = power_budget(text);
    settings.feedback.surprise_floor_share = 0.0;
    App app(settings, Configuration(6, 0), 7, slow);
    const std::vector<Step> steps = app.run(60 * kFps);
    CHECK(app.governor().selections() >= 15);
    const double share = share_of_windows_within(app, steps, settings.power);
    INFO("share of 1-s windows within the budget " << share);
    CHECK(share >= 0.95);
    check_selections(app, app.governor(), steps, settings.power);
    for (std::size_t k = kConverged; k < steps.size(); ++k) CHECK(steps[k].decision.within_budget);

    App floored(power_budget(text), Configuration(6, 0), 7, slow);
    REQUIRE(floored.governor().settings().feedback.surprise_floor_share > 0.0);
    const std::vector<Step> floored_steps = floored.run(60 * kFps);
    CHECK(share_of_windows_within(floored, floored_steps, settings.power) >= 0.95);
    for (std::size_t k = kConverged; k < floored_steps.size(); ++k) CHECK(floored_steps[k].decision.within_budget);
  }
}

TEST_CASE("budgets at the extremes: 0 %, 100 %, watts under P_m and over P_M", "[loop][extremes]") {
  SECTION("0 %: the cheapest configuration") {
    App app(power_budget("0%"));
    const std::vector<Step> steps = app.run(30 * kFps);
    for (std::size_t k = kConverged; k < steps.size(); k += 7) {
      const Truth truth(app.hidden(), steps[k].record.passes);
      CHECK(truth.power(steps[k].target) <= truth.extreme(false) + kToleranceW);
    }
    // The configuration the selection takes for the cheapest: configurations whose true
    // power is within the measured residuals' scatter of the cheapest's are not told apart.
    const Governor::SelectionTable table = app.governor().last_selection();
    const auto lowest = std::min_element(table.power_w->begin(), table.power_w->end()) - table.power_w->begin();
    CHECK(table.chosen == static_cast<std::size_t>(lowest));
    const Configuration cheapest(6, 2);
    const Truth truth(app.hidden(), steps.back().record.passes);
    CHECK(truth.power(steps.back().target) <= truth.power(cheapest) + kToleranceW);
    CHECK(steps.back().decision.within_budget);
  }
  SECTION("100 %: the best configuration") {
    App app(power_budget("100%"), Configuration(6, 2));
    const std::vector<Step> steps = app.run(30 * kFps);
    for (std::size_t k = kConverged; k < steps.size(); ++k) CHECK(steps[k].decision.next == Configuration(6, 0));
    CHECK(steps.back().decision.est_error == 0.0);
  }
  SECTION("watts under P_m: nothing fits, the cheapest is drawn and said to be over") {
    App app(power_budget("10W"));
    const std::vector<Step> steps = app.run(30 * kFps);
    CHECK(steps.back().decision.budget_w == 10.0);
    CHECK_FALSE(steps.back().decision.within_budget);
    for (std::size_t k = kConverged; k < steps.size(); k += 7) {
      const Truth truth(app.hidden(), steps[k].record.passes);
      CHECK(truth.power(steps[k].target) <= truth.extreme(false) + kToleranceW);
    }
  }
  SECTION("watts over P_M: the best configuration") {
    App app(power_budget("100W"), Configuration(6, 1));
    const std::vector<Step> steps = app.run(30 * kFps);
    CHECK(steps.back().decision.next == Configuration(6, 0));
    CHECK(steps.back().decision.within_budget);
    CHECK(steps.back().decision.budget_w == 100.0);
  }
}

TEST_CASE("error budgets alone: the lowest power within the error", "[loop]") {
  for (double error_budget : {0.0, 0.02, 0.05, 1.0}) {
    INFO("error budget " << error_budget);
    GovernorSettings settings;
    settings.error_budget = error_budget;
    App app(settings);
    const std::vector<Step> steps = app.run(30 * kFps);
    Governor& governor = app.governor();
    CHECK(governor.governing());
    std::vector<double> errors;
    governor.errors().estimate_all(errors);
    int checked = 0;
    for (std::size_t k = kConverged; k < steps.size(); ++k) {
      if (steps[k].decision.event != Event::select) continue;
      ++checked;
      const Truth truth(app.hidden(), steps[k].record.passes);
      double lowest = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < errors.size(); ++i) {
        if (errors[i] <= error_budget) lowest = std::min(lowest, truth.power(governor.space().decode(i)));
      }
      CHECK(governor.errors().estimate(steps[k].target) <= error_budget);
      CHECK(truth.power(steps[k].target) <= lowest + kToleranceW);
      CHECK(steps[k].decision.within_budget);
      CHECK(std::isinf(steps[k].decision.budget_w));
    }
    CHECK(checked >= 5);
    if (error_budget == 0.0) CHECK(steps.back().target == Configuration(6, 0));
    if (error_budget == 1.0) CHECK(steps.back().target == Configuration(6, 2));
  }
}

// Errors that compound: each pass degraded beyond the first makes the whole 40 % worse than
// the sum of the passes' own errors, which is all the table's additive estimate sees.
double compounded_error(const ErrorTable& table, const Configuration& c) {
  const auto degraded = std::count_if(c.begin(), c.end(), [](int level) { return level != 0; });
  return table.estimate(c) * (1.0 + 0.4 * static_cast<double>(std::max<std::ptrdiff_t>(0, degraded - 1)));
}

// The share of probe frames (every 10th, from convergence on, settled at the selection's
// target) whose configuration shown had a true error within the budget, and the mean true
// error shown. (What is drawn during a transition passes between the old and the new target,
// and may exceed both: the paper's filter.)
struct ShownErrors {
  double within = 0.0;
  double mean = 0.0;
  Configuration last;
};
ShownErrors governed_with_error_probes(double error_budget, bool feedback) {
  GovernorSettings settings;
  settings.error_budget = error_budget;
  settings.error_feedback.enabled = feedback;
  App app(settings);
  const ErrorTable table = test_errors(app.governor().space());
  int probes = 0, within = 0;
  double sum = 0.0;
  for (int k = 0; k < 60 * kFps; ++k) {
    const Step step = app.step();
    if (k % 10 != 0) continue;
    const double truth = compounded_error(table, step.record.configuration);
    app.governor().shown_error(step.record.configuration, truth);
    if (k < kConverged || step.record.configuration != step.target || app.governor().transitioning()) continue;
    ++probes;
    sum += truth;
    if (truth <= error_budget) ++within;
  }
  return {static_cast<double>(within) / probes, sum / probes, app.governor().target()};
}

TEST_CASE("under an error budget, the errors probes measure of what is shown correct the estimates", "[loop]") {
  for (double error_budget : {0.02, 0.05}) {
    INFO("error budget " << error_budget);
    const ShownErrors open = governed_with_error_probes(error_budget, false);
    const ShownErrors closed = governed_with_error_probes(error_budget, true);
    INFO("within: " << open.within << " open, " << closed.within << " corrected; mean error " << open.mean << ", "
                    << closed.mean);
    // The additive estimate puts the configuration chosen at the budget, and its true error over it.
    CHECK(open.within < 0.5);
    CHECK(closed.within >= 0.95);
    // Still trading: not the best configuration, whose error is 0.
    CHECK(closed.last != Configuration(6, 0));
    CHECK(closed.mean > 0.5 * error_budget);
  }
}

TEST_CASE("select_within_error: ties, NaN and nothing admitted", "[loop][extremes]") {
  const std::vector<double> power{30.0, 25.0, 25.0, kNaN, 20.0};
  const std::vector<double> error{0.0, 0.02, 0.01, 0.0, kNaN};
  model::Selection s = select_within_error(power, error, 0.02);
  CHECK(s.index == 2);  // 25 W at 0.01 before 25 W at 0.02; NaN error and NaN power never
  CHECK(s.within_budget);
  CHECK(std::isinf(s.budget_w));
  s = select_within_error(power, error, -1.0);
  CHECK(s.index == 0);  // the lowest error
  CHECK_FALSE(s.within_budget);
}

TEST_CASE("the power budget wins when both are set", "[loop]") {
  GovernorSettings both = power_budget("40%");
  both.error_budget = 0.0;  // alone, this would ask for the best configuration
  App with_both(both);
  App power_only(power_budget("40%"));
  CHECK(has_note(with_both.governor(), "power budget wins"));
  CHECK_FALSE(has_note(power_only.governor(), "power budget wins"));
  for (int k = 0; k < 20 * kFps; ++k) {
    const Step a = with_both.step();
    const Step b = power_only.step();
    REQUIRE(a.decision.next == b.decision.next);
    REQUIRE(a.target == b.target);
  }
  CHECK(with_both.governor().target() != Configuration(6, 0));
}

TEST_CASE("the temporal filter moves one pass level at a time over transition_s", "[loop]") {
  GovernorSettings settings = power_budget("0%");
  settings.ordered_transition = false;  // the paper's blend
  App app(settings, Configuration(6, 0));
  Step previous = app.step();
  std::optional<std::int64_t> start_ns;
  Configuration from, to;
  std::vector<Configuration> seen;
  for (int k = 1; k < 10 * kFps; ++k) {
    const Step s = app.step();
    for (std::size_t i = 0; i < 6; ++i) REQUIRE(std::abs(s.decision.next[i] - previous.decision.next[i]) <= 1);
    if (!start_ns && s.decision.event == Event::select) {
      start_ns = s.record.time_ns;
      from = previous.decision.next;
      to = s.target;
      REQUIRE(to != from);
      CHECK(s.decision.next == from);  // t = 0
    } else if (start_ns && app.governor().selections() == 1) {
      const double t = static_cast<double>(s.record.time_ns - *start_ns) * 1e-9;
      CHECK(s.decision.next == model::blend_configurations(from, to, t, settings.transition_s));
      if (t < settings.transition_s) {
        CHECK(app.governor().transitioning());
        // Unless the model's own events (which come first) happened at that frame.
        const Event e = s.decision.event;
        if (e != Event::refit && e != Event::fit && e != Event::check) CHECK(e == Event::transition);
      } else {
        CHECK(s.decision.next == to);
        CHECK_FALSE(app.governor().transitioning());
      }
      if (seen.empty() || seen.back() != s.decision.next) seen.push_back(s.decision.next);
    }
    previous = s;
  }
  REQUIRE(start_ns);
  CHECK(to == Configuration(6, 2));
  // 0 -> 2 in every pass: through level 1, at t/T = 1/4 and 3/4.
  CHECK(seen == std::vector<Configuration>{Configuration(6, 0), Configuration(6, 1), Configuration(6, 2)});
}

TEST_CASE("an ordered transition changes as many levels as the blend at each moment, the cheapest first", "[loop]") {
  GovernorSettings settings = power_budget("0%");
  REQUIRE(settings.ordered_transition);
  App app(settings, Configuration(6, 0));
  Step previous = app.step();
  std::optional<std::int64_t> start_ns;
  Configuration from, to;
  model::TransitionPath path;
  std::vector<Configuration> seen;
  for (int k = 1; k < 10 * kFps; ++k) {
    const Step s = app.step();
    if (!start_ns && s.decision.event == Event::select) {
      start_ns = s.record.time_ns;
      from = previous.decision.next;
      to = s.target;
      path = app.governor().transition_path();
      REQUIRE(to != from);
      CHECK(s.decision.next == from);  // t = 0
    } else if (start_ns && app.governor().selections() == 1) {
      const double t = static_cast<double>(s.record.time_ns - *start_ns) * 1e-9;
      CHECK(s.decision.next == model::along_path(path, t, settings.transition_s));
      CHECK(levels_between(s.decision.next, from) ==
            levels_between(model::blend_configurations(from, to, t, settings.transition_s), from));
      if (t >= settings.transition_s) CHECK(s.decision.next == to);
      CHECK(app.governor().transitioning() == (t < settings.transition_s));
      if (seen.empty() || seen.back() != s.decision.next) seen.push_back(s.decision.next);
    }
    previous = s;
  }
  REQUIRE(start_ns);
  REQUIRE(path.configurations.size() == 13);  // 0 -> 2 in six passes
  CHECK(path.configurations.front() == from);
  CHECK(path.configurations.back() == to);
  // As the blend: six levels at t/T = 1/4, six more at 3/4.
  CHECK(seen.size() == 3);
  // Each step is the one-level move toward the target that the truth says saves most (within
  // the predictions' error): the scene's predictions hold.
  const Truth truth(app.hidden(), previous.record.passes);
  const auto true_power = [&](const Configuration& c) { return truth.power(c); };
  const auto& steps = path.configurations;
  for (std::size_t k = 1; k < steps.size(); ++k)
    CHECK(truth.power(steps[k]) <= least_next_step(steps[k - 1], to, true_power) + kToleranceW);
}

TEST_CASE("under an error budget an ordered transition takes the steps that lose least image first", "[loop]") {
  // The error budget holds the estimated error, not the power: the steps are ordered by it, so
  // that no configuration on the way shows a worse image than the target's (the errors add over
  // the passes, as the stand-in table's do).
  GovernorSettings settings;
  settings.error_budget = 0.05;
  App app(settings, Configuration(6, 0));
  for (int k = 0; k < 10 * kFps && app.governor().selections() == 0; ++k) app.step();
  REQUIRE(app.governor().selections() == 1);
  const model::TransitionPath& path = app.governor().transition_path();
  REQUIRE(path.configurations.size() >= 3);
  const Configuration& to = path.configurations.back();
  const ErrorTable& errors = app.governor().errors();
  const auto estimate = [&](const Configuration& c) { return errors.estimate(c); };
  for (std::size_t k = 1; k < path.configurations.size(); ++k) {
    CHECK(errors.estimate(path.configurations[k]) == Approx(least_next_step(path.configurations[k - 1], to, estimate)));
    CHECK(errors.estimate(path.configurations[k]) <= errors.estimate(to) + 1e-12);
  }
}

TEST_CASE("a transition of 0 s switches at once", "[loop][extremes]") {
  GovernorSettings settings = power_budget("0%");
  settings.transition_s = 0.0;
  App app(settings);
  for (int k = 0; k < 2 * kFps; ++k) {
    const Step s = app.step();
    if (s.decision.event == Event::select) {
      CHECK(s.decision.next == s.target);
      return;
    }
  }
  FAIL("no selection");
}

TEST_CASE("probe frames are not learnt", "[loop]") {
  // The same frames with probes (every 10th, with twice the counts and a tenth of the power,
  // which would move any fit that saw them; drawing no more than the frame, they add nothing
  // to keep under the budget) and without. From a level below the best the two runs decide
  // alike throughout. From the best they do up to the first selection, which there keeps room
  // for the best's stream that probes shown elsewhere draw and those at the best do not
  // (probe_overhead.hpp): the predictions up to it show the model learnt alike.
  for (const Configuration& start : {Configuration{0, 0, 0, 0, 0, 1}, Configuration(6, 0)}) {
    const bool from_best = start == Configuration(6, 0);
    INFO("from " << (from_best ? "the best" : "a level below it"));
    // The meter's windows hold the probes' power (meter_windows): what is compared here is
    // what the model learns, so the two runs read windows without them.
    GovernorSettings settings = power_budget("40%");
    settings.meter_windows = false;
    App with_probes(settings, start);
    std::vector<Step> steps;
    for (int k = 0; k < 20 * kFps; ++k) steps.push_back(with_probes.step(std::nullopt, k % 10 == 5, 0.1));
    Governor without(model::testing::synthetic_profile(), with_probes.hidden().space,
                     test_errors(with_probes.hidden().space), settings);
    int compared = 0;
    int after_probe = 0;
    bool selected = false;
    for (const Step& s : steps) {
      if (s.record.probe) {
        CHECK(std::isnan(s.decision.predicted_w));
        CHECK(s.decision.event != Event::select);
        after_probe = 2;
        continue;
      }
      // The two frames after a probe compare the probe's images: their power is taken for none.
      FrameRecord record = s.record;
      if (after_probe > 0) record.power_w = kNaN;
      after_probe = std::max(0, after_probe - 1);
      const Decision d = without.on_frame(record);
      REQUIRE(d.event == s.decision.event);
      REQUIRE((d.predicted_w == s.decision.predicted_w ||
               (std::isnan(d.predicted_w) && std::isnan(s.decision.predicted_w))));
      ++compared;
      if (from_best && d.event == Event::select) {
        selected = true;
        break;
      }
      REQUIRE(d.next == s.decision.next);
    }
    if (from_best) {
      CHECK(selected);
      CHECK(compared >= kFps);
      continue;
    }
    CHECK(compared == 18 * kFps);
    CHECK(without.model().fits() == with_probes.governor().model().fits());
    CHECK(without.selections() == with_probes.governor().selections());
    CHECK(with_probes.governor().probe_overhead().watts() == 0.0);
  }
}

TEST_CASE("the probes' extra power is kept under the budget with the frames'", "[loop]") {
  // Probe frames (every 10th) draw 1.2 times the frame's power: a fiftieth of a frame's power
  // more in every window, which the user's meter sees and the model, never learning from
  // probes, does not. The governor measures it and keeps it under the budget as a margin, so
  // that windows of all frames, probes included, stay as far within it as windows without
  // probes do.
  struct Run {
    double within = 0.0, mean_excess_w = 0.0, overhead_w = 0.0, margin_w = 0.0, probe_margin_w = 0.0;
  };
  auto run = [](bool probes) {
    App app(power_budget("50%"), Configuration(6, 0), 7, 1 << 20);  // a still camera
    std::vector<Step> steps;
    for (int k = 0; k < 60 * kFps; ++k) steps.push_back(app.step(std::nullopt, probes && k % 10 == 5, 1.2));
    Run r;
    r.overhead_w = app.governor().probe_overhead().watts();
    r.margin_w = app.governor().last_selection().margin_w;
    r.probe_margin_w = app.governor().last_selection().probe_margin_w;
    int windows = 0, within = 0;
    for (std::size_t start = 30 * kFps; start + kFps <= steps.size(); start += kFps) {
      double power = 0.0, limit = 0.0;
      for (std::size_t k = start; k < start + kFps; ++k) {
        power += steps[k].record.power_w / kFps;
        limit += steps[k].decision.budget_w / kFps;
      }
      ++windows;
      within += power <= limit;
      r.mean_excess_w += power - limit;
    }
    r.within = static_cast<double>(within) / windows;
    r.mean_excess_w /= windows;
    return r;
  };
  const Run with = run(true), without = run(false);
  INFO("windows within the budget: " << with.within << " with probes (mean excess " << with.mean_excess_w
                                     << " W, overhead " << with.overhead_w << " W, margin " << with.margin_w << " W), "
                                     << without.within << " without (" << without.mean_excess_w << " W, margin "
                                     << without.margin_w << " W)");
  CHECK(without.overhead_w == 0.0);
  CHECK(with.overhead_w == Approx(0.1 * 0.2 * 48.0).epsilon(0.25));  // a tenth of the frames, 0.2 x ~48 W
  // Kept beside the spread's margin, which differs between the two runs as their windows do.
  CHECK(without.probe_margin_w == 0.0);
  CHECK(with.probe_margin_w >= 0.8 * with.overhead_w);
  CHECK(with.margin_w >= with.probe_margin_w);
  // Left out, the probes would put every window about overhead_w further over the budget.
  CHECK(with.mean_excess_w <= without.mean_excess_w + 0.3 * with.overhead_w);
  CHECK(with.within >= without.within - 0.1);
}

TEST_CASE("probe overhead: the probes' excess times their share, never negative", "[loop][extremes]") {
  ProbeOverhead none;
  CHECK(none.watts() == 0.0);
  CHECK(none.share() == 0.0);
  ProbeOverhead every_fifth;
  for (int k = 0; k < 1000; ++k) every_fifth.add(k % 5 == 4, k % 5 == 4 ? 30.0 : 20.0);
  CHECK(every_fifth.share() == Approx(0.2).epsilon(0.02));
  CHECK(every_fifth.excess_w() == Approx(10.0));
  CHECK(every_fifth.watts() == Approx(2.0).epsilon(0.02));
  ProbeOverhead read_back;  // the comparison read back in the next two frames counts with its probe
  for (int k = 0; k < 1000; ++k)
    read_back.add(k % 10 == 4, k % 10 == 4 ? 30.0 : k % 10 == 5 ? 26.0 : k % 10 == 6 ? 22.0 : 20.0);
  CHECK(read_back.excess_w() == Approx(18.0));
  CHECK(read_back.watts() == Approx(1.8).epsilon(0.02));
  ProbeOverhead scattered;  // a window must fit the probe it holds: the largest of the last ones
  for (int k = 0; k < 200; ++k)
    scattered.add(k % 10 == 4, k % 10 == 4 ? (k % 40 == 4 ? 40.0 : 30.0) : 20.0, k * 100'000'000LL);
  CHECK(scattered.excess_w() < 17.0);
  CHECK(scattered.largest_recent_excess_w() == Approx(20.0));
  CHECK(scattered.whole_excess_margin_w(1.0) == Approx(2.0));
  ProbeOverhead cheaper;  // a probe that costs less than the frame saves nothing
  for (int k = 0; k < 100; ++k) cheaper.add(k % 10 == 9, k % 10 == 9 ? 5.0 : 20.0);
  CHECK(cheaper.excess_w() < 0.0);
  CHECK(cheaper.watts() == 0.0);
  ProbeOverhead unmeasured;  // probes without power, or before any frame with power
  unmeasured.add(true, 40.0);
  for (int k = 0; k < 100; ++k) unmeasured.add(k % 10 == 9, k % 10 == 9 ? std::nan("") : 20.0);
  CHECK(unmeasured.probes_measured() == 0);
  CHECK(unmeasured.watts() == 0.0);
  CHECK(unmeasured.share() > 0.09);
}

TEST_CASE("probe overhead in windows: a probe's whole excess where more windows hold one than a budget may leave over",
          "[loop][extremes]") {
  constexpr std::int64_t kTenthS = 100'000'000;  // 10 frames a second: windows of 10 frames
  auto feed = [](ProbeOverhead& o, int period, bool timed) {
    for (int k = 0; k < 4000; ++k)
      o.add(k % period == period / 2, k % period == period / 2 ? 30.0 : 20.0, timed ? k * kTenthS : -1);
  };
  ProbeOverhead sixtieth;  // one window in six holds a probe: each must fit its 10 W over 10 frames
  feed(sixtieth, 60, true);
  CHECK(sixtieth.frames_per_window(1.0) == Approx(10.0));
  CHECK(sixtieth.watts() == Approx(10.0 / 60).epsilon(0.02));
  CHECK(sixtieth.window_margin_w(1.0, 0.95) == Approx(1.0));
  CHECK(sixtieth.window_margin_w(1.0, 0.60) == Approx(sixtieth.watts()));  // a fifth may hold a probe
  ProbeOverhead rare;                                                      // one window in fifty-five: the mean
  feed(rare, 600, true);
  CHECK(rare.window_margin_w(1.0, 0.95) == Approx(rare.watts()));
  ProbeOverhead dense;  // two probes in every window: every window holds the mean
  feed(dense, 5, true);
  CHECK(dense.window_margin_w(1.0, 0.95) == Approx(dense.watts()));
  CHECK(dense.watts() == Approx(2.0).epsilon(0.02));
  ProbeOverhead untimed;  // no frame rate: the mean
  feed(untimed, 60, false);
  CHECK(untimed.frames_per_window(1.0) == 0.0);
  CHECK(untimed.window_margin_w(1.0, 0.95) == Approx(untimed.watts()));
  ProbeOverhead none;
  CHECK(none.window_margin_w(1.0, 0.95) == 0.0);
}

TEST_CASE("probe overhead is energy: a probe frame that overruns its slot counts for every slot it fills",
          "[loop][extremes]") {
  // 10 frames a second at 10 W; every 20th frame a probe that lasts 2.5 slots at 20 W, the
  // frame after it shortened to half a slot (the pacing catching up) at 20 W, the third at
  // 10.5 W. Its energy over the frames before: 2.5 x 10 + 0.5 x 10 + 0.5 = 30.5 W x slots,
  // 3.05 J; counted a frame each it would be 20.5.
  constexpr std::int64_t kSlotNs = 100'000'000;
  ProbeOverhead overrun;
  std::int64_t t = 0;
  double energy_j = 0.0, excess_j = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const int phase = k % 20;
    const std::int64_t length = phase == 10 ? 5 * kSlotNs / 2 : phase == 11 ? kSlotNs / 2 : kSlotNs;
    const double power = phase == 10 || phase == 11 ? 20.0 : phase == 12 ? 10.5 : 10.0;
    t += length;
    overrun.add(phase == 10, power, t);
    energy_j += power * static_cast<double>(length) * 1e-9;
    if (phase >= 10 && phase <= 12) excess_j += (power - 10.0) * static_cast<double>(length) * 1e-9;
  }
  const double run_s = static_cast<double>(t) * 1e-9;
  // A window of a second that holds a probe holds its 3.05 J over the frames' 10 W.
  CHECK(overrun.whole_excess_margin_w(1.0) == Approx(3.05).epsilon(0.05));
  // The mean: what the probes add to a long reading, energy over time.
  CHECK(overrun.watts() == Approx(excess_j / run_s).epsilon(0.05));
  CHECK(overrun.watts() == Approx(energy_j / run_s - 10.0).epsilon(0.05));
  // A pause in a probe's span (a breakpoint, a shader built on the spot) is not the probe's:
  // the span is left out, and the others still count.
  ProbeOverhead paused;
  t = 0;
  for (int k = 0; k < 2000; ++k) {
    const int phase = k % 20;
    const bool pause = k == 1010;  // the frame after the 51st probe: two seconds at 2 W
    const std::int64_t length = pause         ? 20 * kSlotNs
                                : phase == 10 ? 5 * kSlotNs / 2
                                : phase == 11 ? kSlotNs / 2
                                              : kSlotNs;
    const double power = pause ? 2.0 : phase == 10 || phase == 11 ? 20.0 : phase == 12 ? 10.5 : 10.0;
    t += length;
    paused.add(phase == 10, power, t);
  }
  CHECK(paused.probes_measured() == 99);
  CHECK(paused.whole_excess_margin_w(1.0) == Approx(overrun.whole_excess_margin_w(1.0)).epsilon(0.05));
  CHECK(paused.watts() == Approx(overrun.watts()).epsilon(0.05));
  // Untimed, each frame counts one.
  ProbeOverhead untimed;
  for (int k = 0; k < 2000; ++k) {
    const int phase = k % 20;
    untimed.add(phase == 10, phase == 10 || phase == 11 ? 20.0 : phase == 12 ? 10.5 : 10.0);
  }
  CHECK(untimed.excess_w() == Approx(20.5));
}

TEST_CASE(
    "probe overhead: a sweep is measured however many slots it fills, and probes of one pass stand in for it "
    "until it is",
    "[loop][extremes]") {
  // 10 frames a second at 20 W. Probes of one pass every 20 frames: 1.5 slots at 30 W (15 W x
  // slots over their neighbours). Then the shim sweeps six passes (seven streams): each sweep
  // lasts 5.5 slots, 0.55 s, at 30 W (55 W x slots), every 60 frames.
  constexpr std::int64_t kSlotNs = 100'000'000;
  ProbeOverhead o;
  std::int64_t t = 0;
  auto feed = [&](int frames, int period, std::int64_t probe_slots_x2, int sweep_streams) {
    for (int k = 0; k < frames; ++k) {
      const bool probe = k % period == period / 2;
      t += probe ? probe_slots_x2 * kSlotNs / 2 : kSlotNs;
      o.add(probe, probe ? 30.0 : 20.0, t, false, sweep_streams);
    }
  };
  feed(390, 20, 3, 0);
  REQUIRE(o.probes_measured() == 19);
  // (The probe frames' 0.15 s count in the recent frame rate: a slot is a little longer.)
  const double single = o.largest_recent_excess_w();
  CHECK(single == Approx(15.0).epsilon(0.03));
  // The last probe of one pass is still in its span when the shim starts sweeping: it closes
  // scaled as the stand-in, which it does not replace.
  t += kSlotNs * 3 / 2;
  o.add(true, 30.0, t);
  o.set_sweep_streams(7);
  CHECK(o.largest_recent_excess_w() == Approx(2.25 * single));  // sweep_excess_factor(7)
  CHECK(o.whole_excess_margin_w(1.0) == Approx(3.375).epsilon(0.05));
  for (int k = 0; k < 2; ++k) {
    t += kSlotNs;
    o.add(false, 20.0, t);
  }
  CHECK(o.probes_measured() == 20);
  CHECK(o.largest_recent_excess_w() == Approx(2.25 * single).epsilon(0.03));
  o.set_sweep_streams(7);  // said again every frame: scaled once
  CHECK(o.largest_recent_excess_w() == Approx(2.25 * single).epsilon(0.03));
  CHECK(o.planned_streams() == 7);
  // A sweep of 5.5 slots is no pause: it is measured, and the probes of one pass before it read
  // as sweeps by the ratio of the two kinds measured.
  feed(60, 60, 11, 7);
  REQUIRE(o.probes_measured() == 21);
  CHECK(o.largest_recent_excess_w() == Approx(55.0).epsilon(0.03));
  CHECK(o.excess_w() == Approx(55.0).epsilon(0.03));
  CHECK(o.kind_factor(2) == Approx(single / 55.0).epsilon(0.03));
  // A pass back in the scene: the shim's sweeps off for a while, the probes read as what probes
  // of one pass were measured to draw; back as they were when it sweeps again.
  o.set_sweep_streams(0);
  CHECK(o.planned_streams() == 2);
  CHECK(o.largest_recent_excess_w() == Approx(single).epsilon(0.03));
  o.set_sweep_streams(7);
  CHECK(o.largest_recent_excess_w() == Approx(55.0).epsilon(0.03));
  // Sweeps of three passes (four streams), not measured: from the kind measured four times or
  // more (one sweep is not), by sweep_excess_factor's ratio.
  o.set_sweep_streams(4);
  CHECK(o.largest_recent_excess_w() == Approx(1.5 * single).epsilon(0.03));
  o.set_sweep_streams(7);
  // Past 16 slots a probe frame is a pause (a shader built on the spot): not counted.
  feed(60, 60, 40, 7);
  CHECK(o.probes_measured() == 21);
  // Back to probes of one pass: what they draw.
  o.set_sweep_streams(0);
  feed(60, 20, 3, 0);
  CHECK(o.largest_recent_excess_w() == Approx(single).epsilon(0.05));
}

TEST_CASE(
    "probe overhead: each kind of probe is read at the ratio measured between the kinds, its spread from "
    "every probe",
    "[loop][extremes]") {
  // 10 frames a second at 20 W; probes of one pass draw 10 W x frames over their neighbours,
  // sweeps of three passes (four streams) 18: 1.8 times, where sweep_excess_factor guesses 1.5.
  ProbeOverhead o;
  std::int64_t t = 0;
  const auto feed = [&](int probes, int streams, double excess) {
    for (int k = 0; k < probes * 20; ++k) {
      const bool probe = k % 20 == 10;
      t += 100'000'000;
      o.add(probe, probe ? 20.0 + excess : 20.0, t, false, probe && streams > 2 ? streams : 0);
    }
  };
  CHECK(o.kind_factor(4) == Approx(loop::sweep_excess_factor(4)));  // nothing measured: the guess
  feed(6, 2, 10.0);
  CHECK(o.kind_factor(4) == Approx(1.5));  // one kind measured: the guess from it
  o.set_sweep_streams(4);
  feed(2, 4, 18.0);
  o.set_sweep_streams(0);
  CHECK(o.kind_factor(4) == Approx(1.8).epsilon(0.01));  // each kind as measured
  // Kinds not measured: from the kinds measured four times or more; two sweeps are not yet.
  CHECK(o.kind_factor(3) == Approx(1.25));
  o.set_sweep_streams(4);
  feed(2, 4, 18.0);
  o.set_sweep_streams(0);
  CHECK(o.kind_factor(3) == Approx(1.4).epsilon(0.01));  // between two measured often enough
  // Beyond them: from the nearest by the guess's ratio (18 x 2.25 / 1.5 = 27).
  CHECK(o.kind_factor(7) == Approx(2.7).epsilon(0.01));
  // Ten probes over the two kinds give a spread at once: the quantile reads them all, at the
  // kind asked for, where a record of the one kind held four.
  o.set_keep_share(0.95);
  o.set_sweep_streams(4);
  CHECK(o.largest_recent_excess_w() == Approx(18.0).epsilon(0.01));
  CHECK(o.whole_excess_margin_w(1.0) == Approx(1.8).epsilon(0.01));  // no scatter: the largest

  // A ratio measured is kept within twice and half the guess: one probe of one pass at 4 W x
  // frames against sweeps of two passes at 25 reads 0.4 of them (the guess 0.8), not 0.16.
  ProbeOverhead noisy;
  std::int64_t at = 0;
  for (int k = 0; k < 100; ++k) {
    const bool probe = k % 20 == 10, one_pass = k == 10;
    at += 100'000'000;
    if (k == 20) noisy.set_sweep_streams(3);
    noisy.add(probe, probe ? (one_pass ? 24.0 : 45.0) : 20.0, at, false, probe && !one_pass ? 3 : 0);
  }
  CHECK(noisy.kind_factor(2) == Approx(0.4));
}

TEST_CASE("probe overhead: where every window holds a probe, each fits all but the rarest probe's excess",
          "[loop][extremes]") {
  // 10 frames a second at 20 W, a probe every 12 frames: with its span of three frames, every
  // 1-s window holds one. Each probe's excess scatters between 10 and 20 W x frames.
  const auto excess_of = [](int k) { return 10.0 + static_cast<double>((k * 7) % 11); };
  const auto feed = [&](ProbeOverhead& o) {
    int probes = 0;
    for (int k = 0; k < 480; ++k) {
      const bool probe = k % 12 == 6;
      o.add(probe, probe ? 20.0 + excess_of(probes++) : 20.0, k * 100'000'000LL);
    }
    return probes;
  };
  ProbeOverhead largest_only, kept;
  kept.set_keep_share(0.98);
  const int probes = feed(largest_only);
  REQUIRE(feed(kept) == probes);
  double largest = 0.0, mean = 0.0, squares = 0.0;
  for (int k = probes - 4; k < probes; ++k) largest = std::max(largest, excess_of(k));
  for (int k = probes - 16; k < probes; ++k) mean += excess_of(k) / 16.0;
  for (int k = probes - 16; k < probes; ++k) squares += (excess_of(k) - mean) * (excess_of(k) - mean);
  // Half of the 2 % of windows a 0.98 share leaves over, every window holding a probe: the 99th
  // percentile, 2.326 spreads over the mean.
  const double quantile = mean + 2.326 * std::sqrt(squares / 15.0);
  INFO("largest of the last four " << largest << ", quantile " << quantile);
  REQUIRE(quantile > largest);
  CHECK(largest_only.whole_excess_margin_w(1.0) == Approx(largest / 10.0).epsilon(0.02));
  CHECK(kept.whole_excess_margin_w(1.0) == Approx(quantile / 10.0).epsilon(0.02));
  // The excess of 16 probes in 100 is over the largest of the four before each; none over the
  // quantile.
  int over_largest = 0, over_quantile = 0;
  for (int k = 4; k < probes; ++k) {
    double before = 0.0;
    for (int j = k - 4; j < k; ++j) before = std::max(before, excess_of(j));
    over_largest += excess_of(k) > before;
    over_quantile += excess_of(k) > quantile;
  }
  CHECK(over_largest >= 3);
  CHECK(over_quantile == 0);
  // Probes rare enough that the windows keep their mean: no quantile.
  ProbeOverhead rare;
  rare.set_keep_share(0.98);
  for (int k = 0; k < 24000; ++k) {
    const bool probe = k % 1200 == 6;
    rare.add(probe, probe ? 20.0 + excess_of(k / 1200) : 20.0, k * 100'000'000LL);
  }
  double rare_largest = 0.0;
  for (int k = 16; k < 20; ++k) rare_largest = std::max(rare_largest, excess_of(k));
  CHECK(rare.whole_excess_margin_w(1.0) == Approx(rare_largest / 10.0).epsilon(0.02));
}

TEST_CASE("probe overhead: a probe shown at the best draws one stream fewer than one shown elsewhere",
          "[loop][extremes]") {
  // 10 frames a second at 20 W. A probe shown at the best configuration draws no stream of
  // the best (it is what the app drew): 1 W x frame over its neighbours here, where one shown
  // elsewhere draws 30. Until one shown elsewhere is measured, those at the best stand in for
  // it with the best's stream added (15 W above idle for a frame); then they no longer count.
  constexpr std::int64_t kSlotNs = 100'000'000;
  ProbeOverhead o;
  int k = 0;
  auto feed = [&](int frames, bool shown_best, double probe_excess) {
    for (int end = k + frames; k < end; ++k)
      o.add(k % 20 == 10, k % 20 == 10 ? 20.0 + probe_excess : 20.0, k * kSlotNs, shown_best);
  };
  feed(200, true, 1.0);
  REQUIRE(o.probes_measured() == 10);
  CHECK(o.probes_measured_away() == 0);
  CHECK(o.excess_w() == Approx(1.0));  // no stand-in set: what was measured
  o.set_best_stream_w(15.0);
  CHECK(o.excess_w() == Approx(16.0));
  CHECK(o.largest_recent_excess_w() == Approx(16.0));
  CHECK(o.whole_excess_margin_w(1.0) == Approx(1.6).epsilon(0.01));
  CHECK(o.watts() == Approx(16.0 / 20).epsilon(0.01));
  feed(20, false, 30.0);  // one probe shown elsewhere: it replaces the stand-in at once
  CHECK(o.probes_measured_away() == 1);
  CHECK(o.excess_w() == Approx(30.0));
  CHECK(o.largest_recent_excess_w() == Approx(30.0));
  feed(200, true, 1.0);  // back at the best: the probes elsewhere are still what a budget keeps room for
  CHECK(o.excess_w() == Approx(30.0));
  CHECK(o.largest_recent_excess_w() == Approx(30.0));
  CHECK(o.probes_measured() == 21);
  // For the best itself, what its own probes cost.
  CHECK(o.excess_w(true) == Approx(1.0));
  CHECK(o.largest_recent_excess_w(true) == Approx(1.0));
  CHECK(o.whole_excess_margin_w(1.0, true) == Approx(0.1).epsilon(0.01));
  CHECK(o.window_margin_w(1.0, 0.98, true) == Approx(0.1).epsilon(0.01));  // every window holds one
  CHECK(o.window_margin_w(1.0, 0.98) == Approx(3.0).epsilon(0.01));
  CHECK(o.watts(true) == Approx(1.0 / 20).epsilon(0.01));
  CHECK(o.watts_at_gap(100.0, true) == Approx(0.01));
  CHECK(o.watts_at_gap(100.0) == Approx(0.3));
  ProbeOverhead away_only;  // no probe at the best yet: those elsewhere, the larger, stand in
  for (int j = 0; j < 100; ++j) away_only.add(j % 20 == 10, j % 20 == 10 ? 50.0 : 20.0, j * kSlotNs, false);
  CHECK(away_only.excess_w(true) == Approx(30.0));
  // A stand-in that is not finite leaves the last one.
  ProbeOverhead kept;
  for (int j = 0; j < 100; ++j) kept.add(j % 20 == 10, j % 20 == 10 ? 21.0 : 20.0, j * kSlotNs, true);
  kept.set_best_stream_w(15.0);
  kept.set_best_stream_w(std::nan(""));
  CHECK(kept.excess_w() == Approx(16.0));
  // Probes at the best that cost less than their neighbours: the stand-in is the stream less
  // that, in the mean and in the largest alike.
  ProbeOverhead cheaper;
  for (int j = 0; j < 100; ++j) cheaper.add(j % 20 == 10, j % 20 == 10 ? 18.0 : 20.0, j * kSlotNs, true);
  cheaper.set_best_stream_w(15.0);
  CHECK(cheaper.excess_w() == Approx(13.0));
  CHECK(cheaper.largest_recent_excess_w() == Approx(13.0));
  // A stand-in that is not a power above idle adds nothing.
  ProbeOverhead best_only;
  for (int j = 0; j < 100; ++j) best_only.add(j % 20 == 10, j % 20 == 10 ? 21.0 : 20.0, j * kSlotNs, true);
  for (const double bad : {-5.0, std::nan(""), std::numeric_limits<double>::infinity()}) {
    best_only.set_best_stream_w(bad);
    CHECK(best_only.excess_w() == Approx(1.0));
  }
}

TEST_CASE("one probe per window: the shortest gap that leaves no window two probes' spans", "[loop][extremes]") {
  // Frames a probe's span raises, probes every `gap` frames from frame 0: the most spans any
  // window of `window` consecutive frames touches.
  auto most_spans_in_a_window = [](std::uint64_t gap, std::uint64_t window) {
    std::uint64_t most = 0;
    for (std::uint64_t start = 0; start < 4 * gap + window; ++start) {
      std::uint64_t spans = 0;
      for (std::uint64_t probe = 0; probe < start + window; probe += gap)
        if (probe + kProbeSpanFrames > start) ++spans;  // its span reaches into [start, start + window)
      most = std::max(most, spans);
    }
    return most;
  };
  for (const double frames : {1.0, 2.5, 10.0, 10.2, 30.0, 60.0, 144.0}) {
    const std::uint64_t gap = one_probe_per_window_gap(frames);
    const auto window = static_cast<std::uint64_t>(std::ceil(frames));
    CAPTURE(frames, gap);
    CHECK(most_spans_in_a_window(gap, window) == 1);
    CHECK(most_spans_in_a_window(gap - 1, window) == 2);
  }
  CHECK(one_probe_per_window_gap(10.0) == 12);  // 10 fps, 1-s windows
  CHECK(one_probe_per_window_gap(0.0) == 0);
  CHECK(one_probe_per_window_gap(-1.0) == 0);
  CHECK(one_probe_per_window_gap(std::numeric_limits<double>::infinity()) == 0);
  CHECK(one_probe_per_window_gap(std::numeric_limits<double>::quiet_NaN()) == 0);
}

TEST_CASE("a probe in one window of ten: the windows that hold one are held to the budget too", "[loop]") {
  // A probe every 600 frames at 60 frames a second, drawing three times a frame's power: one
  // window in ten holds one, about 1.6 W over the others (at 10 frames a second a probe every
  // 60 frames does this to one window in six). The selection keeps that whole excess under the
  // budget, not a tenth of it (the mean over all frames): the windows with a probe sit at the
  // budget, the others that much under it. With the mean alone the windows with a probe were
  // about 1.4 W over the budget, every one of them.
  App app(power_budget("50%"), Configuration(6, 0), 7, 1 << 20);  // a still camera
  std::vector<Step> steps;
  for (int k = 0; k < 90 * kFps; ++k) steps.push_back(app.step(std::nullopt, k % 600 == 300, 3.0));
  const ProbeOverhead& overhead = app.governor().probe_overhead();
  const double margin = app.governor().last_selection().margin_w, hit = overhead.excess_w() / kFps;
  int probed = 0, others = 0;
  double probed_excess = 0.0, others_excess = 0.0;  // mean measured power over the budget
  for (std::size_t start = 30 * kFps; start + kFps <= steps.size(); start += kFps) {
    double power = 0.0, limit = 0.0;
    bool probe = false;
    for (std::size_t k = start; k < start + kFps; ++k) {
      power += steps[k].record.power_w / kFps;
      limit += steps[k].decision.budget_w / kFps;
      probe |= steps[k].record.probe;
    }
    (probe ? probed_excess : others_excess) += power - limit;
    ++(probe ? probed : others);
  }
  REQUIRE(probed >= 5);
  probed_excess /= probed;
  others_excess /= others;
  INFO("a probe's excess " << overhead.excess_w() << " W, " << hit << " W a window; mean " << overhead.watts()
                           << " W; margin " << margin << " W; windows with a probe " << probed_excess
                           << " W over the budget, the others " << others_excess << " W");
  CHECK(overhead.window_margin_w(1.0, 0.95) == Approx(hit).epsilon(0.05));
  CHECK(margin >= hit);
  CHECK(probed_excess <= 0.25 * hit);
  CHECK(others_excess <= -0.75 * hit);
}

TEST_CASE("probes whose margin outgrows the room under the budget: the fallback never takes the best", "[loop]") {
  // A probe in every window drawing twenty frames' power: no configuration fits under the
  // budget less the probes' margin, and the selection falls back to the lowest weighed power.
  // The best's weight is lowered by what its own probes spare of that margin; the fallback must
  // not read it as the best's power (the demo's Sponza at 40 %, run C: the best chosen at every
  // selection for 33 s, 9 W over the budget).
  App app(power_budget("40%"), Configuration(6, 0), 7, 1 << 20);  // a still camera
  std::vector<Step> steps;
  // A probe shown at the best draws one stream more; one shown elsewhere draws the best besides.
  for (int k = 0; k < 60 * kFps; ++k) {
    const bool at_best = steps.empty() || steps.back().decision.next == Configuration(6, 0);
    steps.push_back(app.step(std::nullopt, k % kFps == kFps / 2, at_best ? 2.0 : 20.0));
  }
  const Governor::SelectionTable table = app.governor().last_selection();
  const std::size_t cheapest = app.governor().space().index_of(Configuration(6, 2));
  INFO("margin " << table.margin_w << " W (probes " << table.probe_margin_w << "), budget " << table.budget_w
                 << " W; best " << (*table.power_w)[0] << " W weighed " << (*table.weighed_w)[0] << "; cheapest "
                 << (*table.power_w)[cheapest] << " W weighed " << (*table.weighed_w)[cheapest]);
  // The case: nothing fits under budget - margin, and the best is over the budget itself.
  REQUIRE(table.budget_w - table.margin_w < (*table.power_w)[cheapest]);
  REQUIRE((*table.power_w)[0] > table.budget_w);
  std::size_t best_targets = 0;
  for (std::size_t k = 20 * kFps; k < steps.size(); ++k) best_targets += steps[k].target == Configuration(6, 0);
  CHECK(best_targets == 0);  // 2400 of 2400 frames before the fallback weighed the best alike
  CHECK(table.chosen == cheapest);
}

TEST_CASE("the first selection keeps room for probes shown elsewhere, though those at the best cost nothing",
          "[loop]") {
  // A probe shown at the best configuration draws no stream of the best (it is what the app
  // drew), and one shown elsewhere draws it besides the frame: here 2 % of the frame's power
  // over its neighbours at the best, 80 % elsewhere (about the best's power above idle, what
  // the governor takes it to cost until one is measured), every 45 frames, so that every
  // window of a second holds one. The first selection, made while the app drew its best,
  // keeps room for the stream its probes lacked, and its first windows, probes and all, keep
  // at least the room of a run without probes. Taking the probes at the best for any probe, it
  // kept none for them (0.07 W against 0.04 W without probes), and its first windows were
  // 0.19 W under the budget on average against 0.30 W without probes.
  struct Run {
    double first_margin_w = 0.0, mean_excess_w = 0.0, stream_w = 0.0;
    int windows = 0;
  };
  auto run = [](bool probes) {
    App app(power_budget("50%"), Configuration(6, 0), 7, 1 << 20);  // a still camera
    app.set_probe_period(45);
    Run r;
    bool at_best = true;
    std::optional<std::size_t> settled;  // the first frame after the first selection's transition
    std::vector<Step> steps;
    for (int k = 0; k < 40 * kFps; ++k) {
      steps.push_back(app.step(std::nullopt, probes && k % 45 == 20, at_best ? 1.02 : 1.8));
      const Step& s = steps.back();
      at_best = std::all_of(s.decision.next.begin(), s.decision.next.end(), [](int level) { return level == 0; });
      if (s.decision.event == Event::select && app.governor().selections() == 1)
        r.first_margin_w = app.governor().last_selection().margin_w;
      if (!settled && app.governor().selections() >= 1 && !app.governor().transitioning() && !at_best)
        settled = steps.size();
    }
    REQUIRE(settled);
    REQUIRE(*settled + 5 * kFps <= steps.size());
    // The best's power above P_m over a window: what a probe elsewhere adds besides the frame.
    double best_w = 0.0;
    for (int k = 0; k < kFps; ++k) best_w += steps[static_cast<std::size_t>(k)].true_power_w / kFps;
    r.stream_w = (best_w - model::testing::synthetic_profile().p_min_w) / kFps;
    // The first five seconds after it, before the windows' own feedback moves the margin.
    for (std::size_t start = *settled; start + kFps <= *settled + 5 * kFps; start += kFps) {
      for (std::size_t k = start; k < start + kFps; ++k)
        r.mean_excess_w += (steps[k].record.power_w - steps[k].decision.budget_w) / kFps;
      ++r.windows;
    }
    r.mean_excess_w /= r.windows;
    return r;
  };
  const Run probed = run(true), unprobed = run(false);
  const double stream_w = probed.stream_w;
  INFO("first selection's margin " << probed.first_margin_w << " W with probes, " << unprobed.first_margin_w
                                   << " W without; first windows' mean power over the budget " << probed.mean_excess_w
                                   << " W with probes, " << unprobed.mean_excess_w << " W without");
  REQUIRE(probed.windows == 5);
  CHECK(probed.first_margin_w >= unprobed.first_margin_w + 0.75 * stream_w);
  CHECK(probed.mean_excess_w <= unprobed.mean_excess_w);
}

namespace {

struct RareProbeRun {
  double mean_error = 0.0;          // estimated error of what was drawn, after the first minute
  double windows_within = 0.0;      // share of 1-s windows whose measured power kept the budget
  double probed_windows = 0.0;      // share of those windows that held a probe
  std::uint64_t period_wanted = 0;  // the governor's last request
  bool bursts_spaced = false;       // and whether bursts are to keep it
  int streams_fit = 0;              // and the most streams a probe frame is to draw
};

// At 10 frames a second a probe every 60 frames (the shim's settled period) falls into one
// window in six; each probe draws 1.5 times a frame's power, its span about 1.3 W over a window.
// The test plays the shim: probes at the settled period, or at the governor's if longer,
// counted from the last probe.
RareProbeRun run_with_probes_at_ten_fps(double stretch_gain, const char* budget = "50%", double probe_power = 1.5,
                                        int sweepable_streams = 0, double sweep_image_cost = 0.005) {
  GovernorSettings settings = power_budget(budget);
  settings.probe_stretch_gain = stretch_gain;
  settings.sweep_image_cost = sweep_image_cost;
  // The probes' margins alone: the surprise floor would shift the errors these runs compare.
  settings.feedback.surprise_floor_share = 0.0;
  App app(settings, Configuration(6, 0), 7, 1 << 20);  // a still camera
  app.set_frame_ns(100'000'000);
  app.set_sweepable_streams(sweepable_streams);
  constexpr int kFrames = 6000, kWindow = 10, kFirst = 600;
  std::vector<Step> steps;
  std::uint64_t last = 0;
  for (int k = 0; k < kFrames; ++k) {
    const std::uint64_t period = std::max<std::uint64_t>(60, app.governor().probe_period_wanted());
    app.set_probe_period(static_cast<double>(period));
    const auto frame = static_cast<std::uint64_t>(k);
    const bool probe = frame >= 3 && frame % period == 0 && frame - last >= period;
    if (probe) last = frame;
    steps.push_back(app.step(std::nullopt, probe, probe_power));
  }
  RareProbeRun run;
  run.period_wanted = app.governor().probe_period_wanted();
  run.bursts_spaced = app.governor().probe_bursts_spaced();
  run.streams_fit = app.governor().probe_streams_fit();
  for (int k = kFirst; k < kFrames; ++k) run.mean_error += steps[k].decision.est_error / (kFrames - kFirst);
  int windows = 0, within = 0, probed = 0;
  for (int start = kFirst; start + kWindow <= kFrames; start += kWindow) {
    double power = 0.0, limit = 0.0;
    bool probe = false;
    for (int k = start; k < start + kWindow; ++k) {
      power += steps[k].record.power_w / kWindow;
      limit += steps[k].decision.budget_w / kWindow;
      probe |= steps[k].record.probe || (k > 0 && steps[k - 1].record.probe);
    }
    ++windows;
    within += power <= limit;
    probed += probe;
  }
  run.windows_within = static_cast<double>(within) / windows;
  run.probed_windows = static_cast<double>(probed) / windows;
  return run;
}

}  // namespace

TEST_CASE("at 10 frames a second, probes are asked rarer where a probe's whole excess in a window costs quality",
          "[loop]") {
  const RareProbeRun every_sixth = run_with_probes_at_ten_fps(0.0), rare = run_with_probes_at_ten_fps(0.005);
  INFO("estimated error shown: " << every_sixth.mean_error << " with a probe every 60 frames, " << rare.mean_error
                                 << " asked rarer (every " << rare.period_wanted << "); windows within the budget "
                                 << every_sixth.windows_within << " and " << rare.windows_within
                                 << "; windows with a probe " << every_sixth.probed_windows << " and "
                                 << rare.probed_windows);
  CHECK(every_sixth.period_wanted == 0);
  // 10 frames a window and a probe's span of 3: 12 window starts touch a probe, at most 2.5 %
  // of the windows (half of the 5 % a budget may leave over it) hold one: 480 + 1 frames.
  CHECK(rare.period_wanted == 481);
  CHECK_FALSE(rare.bursts_spaced);  // a probe's excess fits: bursts may reselect around it
  CHECK(rare.probed_windows <= 0.03);
  CHECK(every_sixth.probed_windows >= 0.15);
  CHECK(rare.mean_error < every_sixth.mean_error - 0.005);
  CHECK(rare.windows_within >= 0.9);
}

// A low share of a narrow range: the room under the budget is less than a probe's excess
// over a window, for the cheapest configuration too. Rarer probes show no lower error (the
// cheapest is drawn either way), but only they keep the windows with a probe in the budget.
TEST_CASE("probes are asked rarer where no configuration fits a probe's whole excess under the budget", "[loop]") {
  const RareProbeRun settled = run_with_probes_at_ten_fps(0.0, "10%", 4.0),
                     rare = run_with_probes_at_ten_fps(0.005, "10%", 4.0);
  INFO("windows within the budget " << settled.windows_within << " with a probe every 60 frames, "
                                    << rare.windows_within << " asked rarer (every " << rare.period_wanted
                                    << "); windows with a probe " << settled.probed_windows << " and "
                                    << rare.probed_windows << "; estimated error shown " << settled.mean_error
                                    << " and " << rare.mean_error);
  CHECK(settled.windows_within < 0.9);
  CHECK(rare.period_wanted == 481);
  CHECK(rare.bursts_spaced);
  CHECK(rare.probed_windows <= 0.03);
  CHECK(rare.windows_within >= 0.95);
  CHECK(rare.mean_error <= settled.mean_error + 0.005);
}

// Settled probes asked rare keep only their mean under the budget; a burst (a probe found the
// scene moved: every pass again, 10 frames apart) puts one in every window. With the feedback
// on, the first window measured over the budget would select again too, up to a window later:
// off here, so that only the burst can be what selects.
// Seven streams sweep six passes; a sweep's whole excess is 2.25 probes of one pass's
// (sweep_excess_factor). With room under the budget for a probe of one pass's excess but not a
// sweep's, the passes are probed in turn, as many at a time as fit; with room for none, sweeps,
// spaced: a window holding a probe is over the budget either way, and a sweep measures all.
// Here at any cost to the image shown; the next test weighs it.
TEST_CASE("sweeps where a window fits one, else probes of fewer passes each, else rare sweeps", "[loop]") {
  constexpr double kAnyCost = 1.0;
  int last_streams = 0;
  for (const char* budget : {"40%", "50%", "60%"}) {
    const RareProbeRun r = run_with_probes_at_ten_fps(0.005, budget, 1.5, 7, kAnyCost);
    INFO(budget << ": " << r.streams_fit << " streams, bursts spaced " << r.bursts_spaced << ", windows within "
                << r.windows_within);
    CHECK_FALSE(r.bursts_spaced);
    CHECK(r.streams_fit >= last_streams);  // more room, more passes a probe frame
    CHECK(r.windows_within >= 0.95);
    last_streams = r.streams_fit;
  }
  CHECK(run_with_probes_at_ten_fps(0.005, "40%", 1.5, 7, kAnyCost).streams_fit == 2);
  const int at_half = run_with_probes_at_ten_fps(0.005, "50%", 1.5, 7, kAnyCost).streams_fit;
  CHECK(at_half > 2);
  CHECK(at_half < 7);
  // Probes that cost less: sweeps of every pass.
  const RareProbeRun cheap = run_with_probes_at_ten_fps(0.005, "60%", 1.2, 7, kAnyCost);
  CHECK(cheap.streams_fit == 7);
  CHECK_FALSE(cheap.bursts_spaced);
  // A probe of one pass's excess fits nowhere: sweeps, spaced.
  const RareProbeRun none_fits = run_with_probes_at_ten_fps(0.005, "30%", 3.0, 7, kAnyCost);
  CHECK(none_fits.streams_fit == 7);
  CHECK(none_fits.bursts_spaced);
  CHECK(none_fits.windows_within >= 0.95);
}

// The margin a sweep's window needs shows a dearer image; by default only where that costs the
// estimated error shown at most GovernorSettings::sweep_image_cost (0.005) over a probe of one
// pass's margin.
TEST_CASE("probe frames measure more passes at once only where their margin costs the image little", "[loop]") {
  for (const char* budget : {"50%", "60%"}) {
    const RareProbeRun any = run_with_probes_at_ten_fps(0.005, budget, 1.2, 7, 1.0),
                       weighed = run_with_probes_at_ten_fps(0.005, budget, 1.2, 7),
                       none = run_with_probes_at_ten_fps(0.005, budget, 1.2, 7, -1.0);
    INFO(budget << ": streams " << any.streams_fit << " / " << weighed.streams_fit << " / " << none.streams_fit
                << " at any cost / weighed / never; estimated error shown " << any.mean_error << " / "
                << weighed.mean_error << " / " << none.mean_error);
    CHECK(none.streams_fit == 2);  // a negative cost: never more than one pass
    CHECK(weighed.streams_fit <= any.streams_fit);
    CHECK(weighed.streams_fit >= none.streams_fit);
    CHECK(weighed.mean_error <= none.mean_error + 0.005 + 0.002);  // the run's own scatter beside it
    CHECK(any.mean_error >= weighed.mean_error - 0.002);
  }
}

TEST_CASE("a burst of probes beyond what the last selection planned for selects again at once", "[loop]") {
  GovernorSettings settings = power_budget("50%");
  settings.feedback.enabled = false;
  App app(settings, Configuration(6, 0), 7, 1 << 20);
  app.set_frame_ns(100'000'000);
  std::uint64_t last = 0;
  int k = 0;
  // Until mid-way between two selections (every 200 frames).
  for (; k < 3000 || k != static_cast<int>(app.governor().last_selection().frame) + 100; ++k) {
    const std::uint64_t period = std::max<std::uint64_t>(60, app.governor().probe_period_wanted());
    app.set_probe_period(static_cast<double>(period));
    const auto frame = static_cast<std::uint64_t>(k);
    const bool probe = frame >= 3 && frame % period == 0 && frame - last >= period;
    if (probe) last = frame;
    app.step(std::nullopt, probe, 1.5);
  }
  REQUIRE(app.governor().probe_period_wanted() == 481);
  const double mean_margin = app.governor().last_selection().margin_w;
  const std::uint64_t selections = app.governor().selections();
  app.set_probe_period(10.0);
  int selected_after = -1;
  for (int j = 0; j < 30 && selected_after < 0; ++j, ++k) {
    const Step s = app.step(std::nullopt, j % 10 == 0, 1.5);
    if (s.decision.event == Event::select) selected_after = j;
  }
  const double whole = app.governor().probe_overhead().whole_excess_margin_w(1.0);
  INFO("margin " << mean_margin << " W before the burst, " << app.governor().last_selection().margin_w
                 << " W after; a probe's whole excess in a window " << whole << " W");
  CHECK(selected_after >= 0);
  CHECK(selected_after == 1);  // the probe frame is never selected at; the frame after it is
  CHECK(app.governor().selections() == selections + 1);
  CHECK(app.governor().last_selection().margin_w >= mean_margin + 0.9 * whole);
  // Not again at every probe of the burst: the selection has planned for it.
  for (int j = 0; j < 60; ++j) CHECK(app.step(std::nullopt, j % 10 == 0, 1.5).decision.event != Event::select);
}

TEST_CASE("meter window: each frame's power over its own interval, frames without power left out", "[loop][extremes]") {
  MeterWindow meter(1.0);
  const std::int64_t ms = 1'000'000;
  CHECK_FALSE(meter.add(0, 50.0, false));  // the first frame only marks the time
  // Nine frames of 100 ms at 10 W, then one of 100 ms at 110 W: 20 W over the second.
  for (int k = 1; k <= 9; ++k) CHECK_FALSE(meter.add(k * 100 * ms, 10.0, false));
  std::optional<MeterWindow::Reading> w = meter.add(1000 * ms, 110.0, false);
  REQUIRE(w);
  CHECK(w->watts == Approx(20.0));
  CHECK(w->probes == 0);
  CHECK(w->frames == 10);
  CHECK(w->span_s == Approx(1.0));
  CHECK(std::isnan(w->budget_w));  // no budget given
  // A probe frame that lasts three slots counts three: 300 ms at 40 W and 700 ms at 10 W.
  CHECK_FALSE(meter.add(1300 * ms, 40.0, true));
  for (int k = 1; k < 7; ++k) CHECK_FALSE(meter.add((1300 + 100 * k) * ms, 10.0, false));
  w = meter.add(2000 * ms, 10.0, false);
  REQUIRE(w);
  CHECK(w->watts == Approx(19.0));
  CHECK(w->probes == 1);
  // Frames without power: their intervals are not counted; half a window without is no reading.
  for (int k = 1; k <= 4; ++k) CHECK_FALSE(meter.add((2000 + 100 * k) * ms, kNaN, false));
  for (int k = 5; k < 10; ++k) CHECK_FALSE(meter.add((2000 + 100 * k) * ms, 30.0, false));
  w = meter.add(3000 * ms, 30.0, false);
  REQUIRE(w);
  CHECK(w->watts == Approx(30.0));
  for (int k = 1; k <= 6; ++k) CHECK_FALSE(meter.add((3000 + 100 * k) * ms, kNaN, false));
  for (int k = 7; k < 10; ++k) CHECK_FALSE(meter.add((3000 + 100 * k) * ms, 30.0, false));
  w = meter.add(4000 * ms, 30.0, false);
  REQUIRE(w);  // closed, but not a meter's reading
  CHECK_FALSE(w->measured());
  CHECK(w->frames == 10);
  CHECK(w->span_s == Approx(1.0));
  // A frame handed over out of order is skipped, the window kept: 500 ms at 8 W, 500 ms at 12 W.
  for (int k = 1; k <= 5; ++k) CHECK_FALSE(meter.add((4000 + 100 * k) * ms, 8.0, false));
  CHECK_FALSE(meter.add(4450 * ms, 1000.0, false));
  for (int k = 6; k < 10; ++k) CHECK_FALSE(meter.add((4000 + 100 * k) * ms, 12.0, false));
  w = meter.add(5000 * ms, 12.0, false);
  REQUIRE(w);
  CHECK(w->watts == Approx(10.0));
  CHECK(w->frames == 10);  // the one out of order not among them
  // Interrupted, or a clock from before the window (a new clock): the next frame starts afresh.
  meter.add(5100 * ms, 5.0, true);
  meter.interrupt();
  CHECK_FALSE(meter.add(9000 * ms, 500.0, false));
  CHECK_FALSE(meter.add(8000 * ms, 500.0, false));
  for (int k = 1; k < 10; ++k) CHECK_FALSE(meter.add((8000 + 100 * k) * ms, 7.0, false));
  w = meter.add(9000 * ms, 7.0, false);
  REQUIRE(w);
  CHECK(w->watts == Approx(7.0));
  CHECK(w->probes == 0);
  // A window's budget is the mean of its frames' given ones, frames without one left out.
  for (int k = 1; k < 10; ++k)
    CHECK_FALSE(meter.add((9000 + 100 * k) * ms, 7.0, false, k <= 3 ? 20.0 : k <= 6 ? kNaN : 30.0));
  w = meter.add(10'000 * ms, 7.0, false, 30.0);
  REQUIRE(w);
  CHECK(w->budget_w == Approx((3 * 20.0 + 4 * 30.0) / 7));
}

TEST_CASE("budget watch: told once, when 8 of the last 10 windows measured over the budget", "[loop][extremes]") {
  const std::int64_t ms = 1'000'000;
  SECTION("every window over: the verdict with the tenth, then never again") {
    BudgetWatch watch;
    std::optional<BudgetWatch::Verdict> v;
    std::int64_t t = 0;
    for (; t <= 10'000 * ms && !v; t += 50 * ms) v = watch.add(t, 30.0, 25.0);
    REQUIRE(v);
    CHECK(t - 50 * ms == 10'000 * ms);  // the tenth window closes at 10 s
    CHECK(v->over == 10);
    CHECK(v->of == 10);
    CHECK(v->measured_w == Approx(30.0));
    CHECK(v->budget_w == 25.0);
    CHECK(v->frames_per_s == Approx(20.0));
    for (; t < 30'000 * ms; t += 50 * ms) CHECK_FALSE(watch.add(t, 30.0, 25.0));
  }
  SECTION("7 of every 10 windows over: never") {
    BudgetWatch watch;
    for (std::int64_t t = 0; t < 60'000 * ms; t += 100 * ms)
      CHECK_FALSE(watch.add(t, (t / (1000 * ms)) % 10 < 7 ? 30.0 : 20.0, 25.0));
  }
  SECTION("each window against the budget in force when it closed") {
    BudgetWatch watch;
    std::optional<BudgetWatch::Verdict> v;
    // 30 W throughout; the budget is 35 W for 3 s and 25 W after: windows 4-11 are over, and
    // the verdict gives their mean budget.
    std::int64_t t = 0;
    for (; t < 20'000 * ms && !v; t += 100 * ms) v = watch.add(t, 30.0, t <= 3000 * ms ? 35.0 : 25.0);
    REQUIRE(v);
    CHECK(t - 100 * ms == 11'000 * ms);
    CHECK(v->over == 8);
    CHECK(v->budget_w == Approx((2 * 35.0 + 8 * 25.0) / 10));
  }
  SECTION("a window's budget is its frames' mean; within 3 % of it is not over") {
    BudgetWatch watch;
    // Half of each window's frames under a budget of 20 W and half under 40 W: 30 W is within.
    for (std::int64_t t = 0; t < 20'000 * ms; t += 100 * ms)
      CHECK_FALSE(watch.add(t, 30.0, (t / (100 * ms)) % 2 ? 20.0 : 40.0));
    for (std::int64_t t = 20'000 * ms; t < 40'000 * ms; t += 100 * ms) CHECK_FALSE(watch.add(t, 30.8, 30.0));
    std::optional<BudgetWatch::Verdict> v;
    for (std::int64_t t = 40'000 * ms; t < 60'000 * ms && !v; t += 100 * ms) v = watch.add(t, 31.0, 30.0);
    REQUIRE(v);  // 30.8 W is within 3 % of 30 W, 31 W is not: the eighth window at 31 W tells
    CHECK(v->over == 8);
    CHECK(v->measured_w == Approx((2 * 30.8 + 8 * 31.0) / 10).margin(0.01));  // a frame of 30.8 W in a window at 31
  }
  SECTION("no budget in force, windows without power, a new clock") {
    BudgetWatch watch;
    const double inf = std::numeric_limits<double>::infinity();
    for (std::int64_t t = 0; t < 20'000 * ms; t += 100 * ms) CHECK_FALSE(watch.add(t, 30.0, t % 2 ? kNaN : inf));
    // Frames without power measure nothing: their windows are not over.
    for (std::int64_t t = 0; t < 20'000 * ms; t += 100 * ms) CHECK_FALSE(watch.add(t, kNaN, 25.0));
    // Nor do those with power for less than half of them, as a meter reads them (MeterWindow).
    for (std::int64_t t = 20'000 * ms; t < 40'000 * ms; t += 100 * ms)
      CHECK_FALSE(watch.add(t, (t / (100 * ms)) % 10 < 4 ? 30.0 : kNaN, 25.0));
    // 9 windows over, then a clock from before them: the open window starts afresh, the nine
    // are kept, and the next window over is the tenth.
    BudgetWatch again;
    for (std::int64_t t = 0; t <= 9000 * ms; t += 100 * ms) CHECK_FALSE(again.add(t, 30.0, 25.0));
    CHECK_FALSE(again.add(500 * ms, 30.0, 25.0));
    std::optional<BudgetWatch::Verdict> v;
    for (std::int64_t t = 600 * ms; t <= 1500 * ms && !v; t += 100 * ms) v = again.add(t, 30.0, 25.0);
    REQUIRE(v);
    CHECK(v->over == 10);
    // A frame handed over out of order inside a window is skipped as a meter skips it: the
    // window is kept, and the tenth closes at 10 s.
    BudgetWatch skips;
    v.reset();
    std::int64_t t = 0;
    for (; t <= 10'000 * ms && !v; t += 100 * ms) {
      v = skips.add(t, 30.0, 25.0);
      if (t == 9500 * ms) CHECK_FALSE(skips.add(9450 * ms, 30.0, 25.0));
    }
    REQUIRE(v);
    CHECK(t - 100 * ms == 10'000 * ms);
  }
}

TEST_CASE("a budget no configuration reaches: the governor says so once, and whether unpaced frames may be why",
          "[loop]") {
  // The synthetic app draws 60 frames a second: paced by the shim at 60, not paced, or paced
  // at a rate its frames do not keep up with.
  for (const double paced_fps : {60.0, 0.0, 100.0}) {
    INFO("paced at " << paced_fps);
    GovernorSettings settings = power_budget("10W");
    settings.paced_fps = paced_fps;
    App app(settings);
    app.run(30 * kFps);
    std::size_t told = 0;
    for (const std::string& note : app.governor().notes()) told += note.find("not being kept") != std::string::npos;
    CHECK(told == 1);
    CHECK(has_note(app.governor(), "against 10.0 W) at 60 frames a second"));
    CHECK(has_note(app.governor(), "raise the budget") == (paced_fps == 60.0));
    CHECK(has_note(app.governor(), "give --fps N") == (paced_fps == 0.0));
    CHECK(has_note(app.governor(), "give a lower --fps") == (paced_fps == 100.0));
  }
  // A budget kept says nothing.
  GovernorSettings settings = power_budget("50%");
  settings.paced_fps = 0.0;
  App app(settings);
  app.run(30 * kFps);
  CHECK_FALSE(has_note(app.governor(), "not being kept"));
}

TEST_CASE("a meter's window over the budget selects again at once (meter_windows), and one under it does not",
          "[loop]") {
  // The feedback off, so that the meter is the only measured check; a still camera, 10 frames a
  // second. Mid-way between two selections the frames measure 2 W over the budget (or 1 W under).
  auto frames_to_reselect = [](bool meter, double over_w) {
    GovernorSettings settings = power_budget("50%");
    settings.feedback.enabled = false;
    settings.meter_windows = meter;
    App app(settings, Configuration(6, 0), 7, 1 << 20);
    app.set_frame_ns(100'000'000);
    int k = 0;
    for (; k < 5000 && (k < 1000 || k != static_cast<int>(app.governor().last_selection().frame) + 60); ++k) app.step();
    REQUIRE(k < 5000);  // settled 60 frames after a selection
    const double budget = app.governor().last_selection().budget_w;
    for (int j = 1; j <= 40; ++j) {
      if (app.step(budget + over_w).decision.event == Event::select) return j;
    }
    return -1;
  };
  // The meter's window open when the frames rose may close under the budget; the next closes over it.
  const int meter_on = frames_to_reselect(true, 2.0);
  CHECK(meter_on >= 1);
  CHECK(meter_on <= 21);
  CHECK(frames_to_reselect(false, 2.0) == -1);
  CHECK(frames_to_reselect(true, -1.0) == -1);
}

TEST_CASE("a meter's window closed by a probe waits for the feedback's window before selecting again", "[loop]") {
  // 10 frames a second, a still camera; every configuration but the best draws 6 W more than
  // the model can see. The first configuration chosen is over the budget by that much. A probe
  // lands on the frame that closes the meter's first window there: the meter reads the window
  // over the budget at once, while the feedback, which leaves the probe and the two frames after
  // it out, has not closed its own yet. The selection waits for it, so that it counts on the
  // configuration as measured rather than on the prediction that put the window over (the demo's
  // Sponza at 40 %: selecting at once, the next pick was predicted 5 W under what it drew).
  GovernorSettings settings = power_budget("70%");
  App app(settings, Configuration(6, 0), 7, 1 << 20, [](const Configuration& c) {
    return std::any_of(c.begin(), c.end(), [](int l) { return l > 0; }) ? 6.0 : 0.0;
  });
  app.set_frame_ns(100'000'000);
  int k = 0;
  // Probes every 15 frames until the first selection, as the shim's first probes of each pass:
  // what a probe costs is known when the governor selects.
  for (; k < 2000 && app.governor().last_selection().frame == 0; ++k) app.step(std::nullopt, k % 15 == 10, 3.0);
  REQUIRE(k < 2000);
  REQUIRE(app.governor().probe_overhead().probes_measured() > 0);
  const Configuration first = app.governor().target();
  REQUIRE(first != Configuration(6, 0));
  const std::size_t first_index = app.governor().space().index_of(first);
  const double predicted_first = (*app.governor().last_selection().weighed_w)[first_index];
  // Settled at the first target: the meter's window starts there and closes ten frames on.
  int settled = -1;
  for (int j = 0; j < 100 && settled < 0; ++j, ++k) {
    const bool transitioning = app.governor().transitioning();
    if (app.step().record.configuration == first && !transitioning) settled = k;
  }
  REQUIRE(settled >= 0);
  std::optional<std::uint64_t> reselected;
  double drawn_w = 0.0;  // the first configuration's frames before the probe, as measured
  int drawn = 0;
  for (int j = 1; j <= 40 && !reselected; ++j, ++k) {
    const Step s = app.step(std::nullopt, k == settled + 10, 3.0);
    if (k < settled + 10) {
      drawn_w += s.record.power_w;
      ++drawn;
    }
    if (s.decision.event == Event::select || s.decision.event == Event::explore) reselected = s.record.frame;
  }
  REQUIRE(reselected);
  drawn_w /= drawn;
  INFO("first " << ::Catch::Detail::stringify(first) << " settled at frame " << settled << ", selected again at "
                << *reselected << "; it drew " << drawn_w << " W, weighed at " << predicted_first
                << " W at the first selection");
  REQUIRE(drawn_w > predicted_first + 2.0);  // the window was a surprise
  CHECK(*reselected > static_cast<std::uint64_t>(settled + 10));
  // The configuration first chosen is measured, at its window's power, when the selection weighs it.
  CHECK(app.governor().feedback().measured(first));
  const double weighed = (*app.governor().last_selection().weighed_w)[first_index];
  CHECK(weighed == Approx(drawn_w).margin(1.0));
}

TEST_CASE("power missing for hold_after_missing_power frames holds the configuration", "[loop]") {
  App app(power_budget("40%"));
  Step previous = app.run(15 * kFps).back();
  for (int spell = 0; spell < 2; ++spell) {
    Configuration held;
    for (int missing = 1; missing <= 5 * kFps; ++missing) {
      const Step s = app.step(kNaN);
      if (missing < 30) {
        CHECK(s.decision.event != Event::hold);
        CHECK_FALSE(app.governor().holding());
      } else {
        if (missing == 30) held = previous.decision.next;  // a transition stops where it is
        CHECK(s.decision.event == Event::hold);
        CHECK(app.governor().holding());
        CHECK_FALSE(app.governor().transitioning());
        CHECK(s.decision.next == held);
        CHECK(app.governor().target() == held);
        CHECK(std::isfinite(s.decision.predicted_w));  // counts are still predicted
      }
      previous = s;
    }
    const Step back = app.step();
    CHECK(back.decision.event != Event::hold);
    CHECK_FALSE(app.governor().holding());
    previous = app.run(5 * kFps).back();
  }
  int holding_notes = 0;
  for (const std::string& note : app.governor().notes()) holding_notes += note.find("holding") != std::string::npos;
  CHECK(holding_notes == 1);
}

TEST_CASE("a sensor that never gives power: no fit, no selection, a hold", "[loop][extremes]") {
  App app(power_budget("40%"), Configuration{1, 0, 2, 0, 0, 1});
  for (int k = 0; k < 100; ++k) {
    const Step s = app.step(kNaN);
    CHECK(s.decision.next == Configuration{1, 0, 2, 0, 0, 1});
    CHECK(std::isnan(s.decision.predicted_w));
    CHECK(std::isnan(s.decision.budget_w));  // a share of the range needs predictions
    CHECK(s.decision.event == (k >= 29 ? Event::hold : Event::none));
  }
  CHECK(app.governor().selections() == 0);
}

TEST_CASE("without a budget nothing changes", "[loop]") {
  const Configuration forced{1, 0, 2, 0, 0, 1};
  App app(GovernorSettings{}, forced);
  CHECK_FALSE(app.governor().governing());
  CHECK(has_note(app.governor(), "observing only"));
  bool fitted = false;
  for (const Step& s : app.run(20 * kFps)) {
    CHECK(s.decision.next == forced);
    CHECK(s.decision.event != Event::select);
    CHECK(s.decision.event != Event::transition);
    CHECK(std::isinf(s.decision.budget_w));
    fitted = fitted || s.decision.event == Event::fit;
  }
  CHECK(fitted);  // it still learns, for the log
  CHECK(app.governor().selections() == 0);

  // A frame outside the space is passed through as it is.
  FrameRecord odd;
  odd.configuration = {7};
  odd.power_w = 30.0;
  const Decision d = app.governor().on_frame(odd);
  CHECK(d.next == Configuration{7});
  CHECK(std::isnan(d.est_error));
}

TEST_CASE("an invalid error budget is ignored with a note", "[loop][extremes]") {
  for (double bad : {-0.1, kNaN, std::numeric_limits<double>::infinity()}) {
    GovernorSettings settings;
    settings.error_budget = bad;
    App app(settings);
    CHECK_FALSE(app.governor().governing());
    CHECK(has_note(app.governor(), "error budget"));
  }
}

TEST_CASE("per-step timings are kept", "[loop]") {
  App app(power_budget("40%"));
  app.run(20 * kFps);
  const StepTimes& times = app.governor().step_times();
  CHECK(times.predict_frame.count == 20 * kFps);
  CHECK(times.learn.count == 20 * kFps);
  CHECK(times.fit.count == app.governor().model().fits());
  CHECK(times.predict_all.count == app.governor().selections());
  CHECK(times.estimate_errors.count == app.governor().selections());
  CHECK(times.select.count == app.governor().selections());
  for (const RunningStats* s : {&times.learn, &times.fit, &times.predict_all, &times.select}) {
    CHECK(s->mean_us > 0.0);
    CHECK(s->mean_us <= s->max_us);
    CHECK(s->last_us <= s->max_us);
  }
  CHECK(describe(times).find("predict all") != std::string::npos);
  CHECK(std::string(event_name(Event::transition)) == "transition");
}

TEST_CASE("running statistics", "[loop]") {
  RunningStats stats;
  for (double us : {4.0, 1.0, 7.0}) stats.add(us);
  CHECK(stats.count == 3);
  CHECK(stats.last_us == 7.0);
  CHECK(stats.mean_us == Approx(4.0));
  CHECK(stats.max_us == 7.0);
}

TEST_CASE("the stand-in error table", "[loop][errors]") {
  std::vector<model::PassVariants> passes;
  for (std::size_t levels : {3, 1, 2, 5}) {
    passes.push_back({"p" + std::to_string(levels), std::vector<model::VariantCost>(levels), {}});
  }
  const model::ConfigurationSpace space(passes);
  ErrorTable table(space);
  CHECK(table.fits(space));
  CHECK(table.size() == space.size());
  CHECK(table.error(0, 0) == 0.0);
  CHECK(table.error(0, 1) == Approx(0.005));
  CHECK(table.error(0, 2) == Approx(0.01));
  CHECK(table.error(1, 0) == 0.0);
  CHECK(table.error(3, 1) == Approx(0.0025));
  CHECK(table.error(3, 4) == Approx(0.01));
  CHECK(ErrorTable::stand_in(2, 3) == Approx(0.01));
  CHECK(ErrorTable::stand_in(0, 1) == 0.0);
  CHECK_FALSE(table.is_stand_in(0, 0));
  CHECK(table.is_stand_in(0, 1));
  CHECK(table.stand_in_passes() == std::vector<std::string>{"p3", "p2", "p5"});

  CHECK(table.set(0, 1, 0.2));
  CHECK(table.set(0, 2, 0.3));
  CHECK_FALSE(table.set(0, 0, 0.1));  // the reference
  CHECK_FALSE(table.set(0, 3, 0.1));
  CHECK_FALSE(table.set(9, 1, 0.1));
  CHECK_FALSE(table.set(2, 1, kNaN));
  CHECK_FALSE(table.set(2, 1, -0.1));
  CHECK(table.stand_in_passes() == std::vector<std::string>{"p2", "p5"});
  CHECK(std::isnan(table.estimate({0, 0, 0})));
  CHECK(std::isnan(table.estimate({0, 1, 0, 0})));

  std::vector<double> all{1.0, 2.0};  // stale contents are overwritten
  table.estimate_all(all);
  REQUIRE(all.size() == space.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const Configuration c = space.decode(i);
    double sum = 0.0;
    for (std::size_t p = 0; p < c.size(); ++p) sum += table.error(p, c[p]);
    CHECK(all[i] == Approx(sum).margin(1e-15));
    CHECK(table.estimate(c) == Approx(sum).margin(1e-15));
  }
  CHECK(all[0] == 0.0);

  std::vector<model::PassVariants> renamed = passes;
  renamed[1].pass = "other";
  CHECK_FALSE(table.fits(model::ConfigurationSpace(renamed)));
  renamed = passes;
  renamed[2].levels.resize(3);
  CHECK_FALSE(table.fits(model::ConfigurationSpace(renamed)));

  const ErrorTable empty{model::ConfigurationSpace{}};
  std::vector<double> one;
  empty.estimate_all(one);
  CHECK(one == std::vector<double>{0.0});
}

TEST_CASE("the governor says when its errors are stand-ins, and replaces a table that does not fit", "[loop][errors]") {
  const HiddenModel hidden = model::testing::six_pass_hidden_model();
  const Governor stand_in(model::testing::synthetic_profile(), hidden.space, ErrorTable(hidden.space),
                          power_budget("40%"));
  CHECK(has_note(stand_in, "stand-in"));
  CHECK(has_note(stand_in, "resolution, shading, reflections, shadows, metals, antialiasing"));
  const Governor measured(model::testing::synthetic_profile(), hidden.space, test_errors(hidden.space),
                          power_budget("40%"));
  CHECK(measured.notes().empty());
  const Governor mismatched(model::testing::synthetic_profile(), hidden.space, ErrorTable{}, power_budget("40%"));
  CHECK(has_note(mismatched, "does not match"));
  CHECK(mismatched.errors().fits(hidden.space));
}

TEST_CASE("errors from the manifest, stand-ins where a level has none", "[loop][errors]") {
  const manifest::LoadResult loaded = manifest::parse_manifest(R"toml([[pass]]
name = "a"
[[pass.level]]
[[pass.level]]
error = 0.03
[[pass.level]]
[[pass]]
name = "b"
[[pass.level]]
[[pass.level]]
error = 0.2
)toml",
                                                               "m.toml");
  REQUIRE(loaded.manifest);
  const ErrorTable table = errors_from_manifest(*loaded.manifest);
  CHECK(table.error(0, 1) == 0.03);
  CHECK_FALSE(table.is_stand_in(0, 1));
  CHECK(table.error(0, 2) == Approx(0.01));
  CHECK(table.is_stand_in(0, 2));
  CHECK(table.error(1, 1) == 0.2);
  CHECK(table.stand_in_passes() == std::vector<std::string>{"a"});
  CHECK(table.fits(space_from_manifest(*loaded.manifest)));
}

TEST_CASE("space_from_manifest with measured costs", "[loop][manifest]") {
  const manifest::LoadResult loaded = manifest::parse_manifest(R"toml(
[[pass]]
name = "a"
match = { source = "A" }
[[pass.level]]
[[pass.level]]
defines = { N = 1 }
[[pass]]
name = "b"
match = { source = "B" }
[[pass.level]]
[[pass.level]]
draws = false
[[pass]]
name = "c"
match = { source = "C" }
[[pass.level]]
)toml",
                                                               "m.toml");
  REQUIRE(loaded.manifest);
  // "a" measured; "b" measured with another number of levels; "c" absent; "z" not in the manifest.
  const auto table = model::parse_variant_table(R"json({"passes": [
        {"name": "a", "levels": [{"hashes": ["0000000000000001"], "ins_v": 10, "ins_f": 300, "tex_f": 4},
                                 {"hashes": ["0000000000000002"], "ins_v": 10, "ins_f": 30, "tex_f": 1}]},
        {"name": "b", "levels": [{"hashes": ["0000000000000003"], "ins_v": 1, "ins_f": 2, "tex_f": 3}]},
        {"name": "z", "levels": [{"hashes": ["0000000000000004"], "ins_f": 7}]}]})json",
                                                "t.json");
  REQUIRE(table);
  std::vector<std::string> problems;
  const model::ConfigurationSpace space = space_from_manifest(*loaded.manifest, *table, problems);
  REQUIRE(space.pass_count() == 3);
  const auto& a = space.passes()[0].levels;
  CHECK(a[0].ins_v == 10.0);
  CHECK(a[0].ins_f == 300.0);
  CHECK(a[0].tex_f == 4.0);
  CHECK(a[1].ins_f == 30.0);
  CHECK(a[1].tex_f == 1.0);
  const auto& b = space.passes()[1].levels;
  CHECK(b[0].ins_f == 0.0);
  CHECK_FALSE(b[1].draws);  // the manifest's, whatever the table says
  CHECK(space.passes()[2].levels[0].ins_f == 0.0);
  REQUIRE(problems.size() == 1);
  CHECK(problems[0].find("pass 'b' has 2 levels in the manifest and 1 in the measured costs") != std::string::npos);
  // The same space as without costs in everything but the costs.
  CHECK(space.size() == space_from_manifest(*loaded.manifest).size());
}

TEST_CASE("space_from_manifest on the demo's manifest", "[loop][manifest]") {
  const manifest::LoadResult loaded =
      manifest::load_manifest(std::string(GLBUDGET_SOURCE_DIR) + "/testapps/demo/glbudget.toml");
  REQUIRE(loaded.manifest);
  const model::ConfigurationSpace space = space_from_manifest(*loaded.manifest);
  REQUIRE(space.pass_count() == 6);
  CHECK(space.size() == 729);
  const std::vector<std::string> names{"resolution", "base", "reflections", "shadows", "metals", "antialiasing"};
  for (std::size_t i = 0; i < 6; ++i) {
    const model::PassVariants& pass = space.passes()[i];
    CHECK(pass.pass == names[i]);
    REQUIRE(pass.levels.size() == 3);
    CHECK(pass.scales == loaded.manifest->passes[i].scales);
    for (const model::VariantCost& cost : pass.levels) {
      CHECK(cost.ins_v == 0.0);
      CHECK(cost.ins_f == 0.0);
      CHECK(cost.tex_f == 0.0);
      CHECK(cost.draws);
    }
  }
  const auto& resolution = space.passes()[0];
  CHECK(resolution.scales == std::vector<std::string>{"base", "metals", "reflections"});
  CHECK(resolution.levels[0].fragment_scale == 1.0);
  CHECK(resolution.levels[1].fragment_scale == Approx(0.64));
  CHECK(resolution.levels[2].fragment_scale == Approx(0.36));
  const auto& shadows = space.passes()[3];
  CHECK(shadows.scales == std::vector<std::string>{"shadows"});
  CHECK(shadows.levels[1].fragment_scale == Approx(0.25));
  CHECK(shadows.levels[2].fragment_scale == Approx(0.0625));
  CHECK(space.passes()[1].levels[2].fragment_scale == 1.0);

  // The demo's manifest gives no errors yet: all stand-ins.
  const ErrorTable errors = errors_from_manifest(*loaded.manifest);
  CHECK(errors.fits(space));
  CHECK(errors.stand_in_passes().size() == 6);

  // A level that skips its draws.
  const manifest::LoadResult skipping =
      manifest::parse_manifest("[[pass]]\nname = \"r\"\n[[pass.level]]\n[[pass.level]]\ndraws = false\n", "m.toml");
  REQUIRE(skipping.manifest);
  const model::ConfigurationSpace skip_space = space_from_manifest(*skipping.manifest);
  REQUIRE(skip_space.passes()[0].levels.size() == 2);
  CHECK_FALSE(skip_space.passes()[0].levels[1].draws);
}

TEST_CASE("a governor over a manifest's space with a render scale, driven from its manifest", "[loop][manifest]") {
  const manifest::LoadResult loaded =
      manifest::load_manifest(std::string(GLBUDGET_SOURCE_DIR) + "/testapps/demo/glbudget.toml");
  REQUIRE(loaded.manifest);
  const model::ConfigurationSpace space = space_from_manifest(*loaded.manifest);
  Governor governor(model::testing::synthetic_profile(), space, errors_from_manifest(*loaded.manifest),
                    power_budget("50%"));
  // Power falls with every pass's fragments; the render scale and shadow-map size take
  // fragments away, the other passes' levels cost the same (no instrumentation yet).
  Configuration drawn(6, 0);
  std::mt19937_64 random(5);
  std::normal_distribution<double> noise(0.0, 0.1);
  for (std::uint64_t k = 0; k < 600; ++k) {
    FrameRecord record;
    record.frame = k;
    record.time_ns = static_cast<std::int64_t>(k) * kFrameNs;
    record.configuration = drawn;
    double alpha = 0.0;
    for (std::size_t i = 0; i < 6; ++i) {
      double scale = 1.0;
      for (std::size_t s = 0; s < 6; ++s) {
        const auto& scales = space.passes()[s].scales;
        if (std::find(scales.begin(), scales.end(), space.passes()[i].pass) != scales.end()) {
          scale *= space.passes()[s].levels[static_cast<std::size_t>(drawn[s])].fragment_scale;
        }
      }
      const double wave = 1.0 + 0.3 * std::sin(0.01 * static_cast<double>(k) + static_cast<double>(i));
      const model::PassCounts counts{100.0 * wave, 1e6 * wave, 1e8 * scale * wave};
      record.passes.push_back({static_cast<model::PassIndex>(i), counts});
      alpha += 0.4 * counts.fragments / 4e8 + 1.0 * counts.batches / 5000.0;
    }
    record.power_w = model::power_from_alpha(model::testing::synthetic_profile(), alpha) + noise(random);
    const Decision d = governor.on_frame(record);
    REQUIRE(space.contains(d.next));
    drawn = d.next;
  }
  CHECK(governor.selections() >= 2);
  // Only the render scale and the shadow map save power here; at 50 % one of them is lowered.
  CHECK(governor.target() != Configuration(6, 0));
  CHECK((governor.target()[0] > 0 || governor.target()[3] > 0));
  CHECK(has_note(governor, "stand-in"));
}

// A pass whose cheaper levels save power the counts do not show (no instrumented costs, no
// fragments taken away): the model predicts every configuration alike.
struct UnseenKnob {
  model::ConfigurationSpace space;
  explicit UnseenKnob(const char* manifest_text) {
    const manifest::LoadResult loaded = manifest::parse_manifest(manifest_text, "knob.toml");
    REQUIRE(loaded.manifest);
    space = space_from_manifest(*loaded.manifest);
  }
  // Frames of the knob's pass, counts in a slow wave; level l draws saving_w * l watts less.
  std::vector<Step> run(Governor& governor, int frames, double saving_w) const {
    std::vector<Step> steps;
    Configuration drawn(space.pass_count(), 0);
    std::mt19937_64 random(3);
    std::normal_distribution<double> noise(0.0, 0.1);
    for (int k = 0; k < frames; ++k) {
      Step s;
      s.record.frame = static_cast<std::uint64_t>(k);
      s.record.time_ns = static_cast<std::int64_t>(k) * kFrameNs;
      s.record.configuration = drawn;
      const double wave = 1.0 + 0.1 * std::sin(0.01 * k);
      const model::PassCounts counts{100.0 * wave, 1e6 * wave, 1e8 * wave};
      s.record.passes.push_back({0, counts});
      const double alpha = 0.4 * counts.fragments / 4e8 + 1.0 * counts.batches / 5000.0;
      s.true_power_w = model::power_from_alpha(model::testing::synthetic_profile(), alpha) - saving_w * drawn[0];
      s.record.power_w = s.true_power_w + noise(random);
      s.decision = governor.on_frame(s.record);
      s.target = governor.target();
      drawn = s.decision.next;
      steps.push_back(s);
    }
    return steps;
  }
};

const char* kUnseenKnob = R"toml(
[[pass]]
name = "knob"
match.hash = "00000000000000aa"
[[pass.level]]
[[pass.level]]
defines = { CHEAP = 1 }
[[pass.level]]
defines = { CHEAP = 2 }
)toml";

TEST_CASE("a model that cannot tell the configurations apart: the cheapest is measured once", "[loop]") {
  // Every level is predicted at the best's power; each level draws 3 W less than the one
  // before. Under 60 % of the range the governor draws the cheapest for one window
  // (`explore`), then has a range whose low end is measured, selects below the best, and stays
  // within the budget below it. (Where it settles: the refits at the cheapest re-anchor every
  // prediction there, the best's included, and the range shrinks towards the cheapest, so the
  // level chosen is the cheapest rather than the middle one a 60 % budget would admit: a
  // known limit, README's Limits.)
  const UnseenKnob knob(kUnseenKnob);
  Governor governor(model::testing::synthetic_profile(), knob.space, ErrorTable(knob.space), power_budget("60%"));
  const std::vector<Step> steps = knob.run(governor, 40 * kFps, 3.0);
  std::size_t explored = 0, explore_frame = 0;
  for (const Step& s : steps)
    if (s.decision.event == Event::explore) ++explored, explore_frame = s.record.frame;
  REQUIRE(explored == 1);
  const auto first_select =
      std::find_if(steps.begin(), steps.end(), [](const Step& s) { return s.decision.event == Event::select; });
  CHECK(first_select - steps.begin() > static_cast<std::ptrdiff_t>(explore_frame));  // the first selection explores
  // Right after the exploration: the cheapest is the target until its window is measured.
  CHECK(steps[explore_frame].target == Configuration{2});
  // The last 10 s: below the best, and the budget set between the measured ends.
  const double best_w = steps.front().true_power_w;
  double drawn_w = 0.0, budget_w = 0.0;
  for (std::size_t k = steps.size() - 10 * kFps; k < steps.size(); ++k) {
    drawn_w += steps[k].true_power_w / (10 * kFps);
    budget_w += steps[k].decision.budget_w / (10 * kFps);
  }
  INFO("best " << best_w << " W; the last 10 s drew " << drawn_w << " W under a budget of " << budget_w << " W");
  CHECK(budget_w < best_w - 1.5);
  CHECK(drawn_w < best_w - 1.5);
  CHECK(drawn_w <= budget_w + kToleranceW);
  for (std::size_t k = explore_frame; k < steps.size(); ++k) CHECK(steps[k].target != Configuration{0});
}

TEST_CASE("measured at their windows: the best keeps what it drew once refits re-anchor the model at the cheapest",
          "[loop]") {
  // The scene above: after the exploration the refits re-anchor every prediction at the cheapest,
  // the best's included, and the best's residual, measured against the coefficients of the run's
  // first seconds, no longer lifts it to what it drew. Weighed at its windows' power moved by the
  // model's change since their counts (measured_at_windows), the best stays the top of the
  // range as measured, and the budget 60 % of the way up the measured range.
  const UnseenKnob knob(kUnseenKnob);
  constexpr double kSavingW = 3.0;  // a level
  auto run = [&](bool at_windows, double* budget_w, double* drawn_w, double* best_w) {
    GovernorSettings settings = power_budget("60%");
    settings.measured_at_windows = at_windows;
    Governor governor(model::testing::synthetic_profile(), knob.space, ErrorTable(knob.space), settings);
    const std::vector<Step> steps = knob.run(governor, 40 * kFps, kSavingW);
    *budget_w = *drawn_w = *best_w = 0.0;
    for (std::size_t k = steps.size() - 10 * kFps; k < steps.size(); ++k) {
      *drawn_w += steps[k].true_power_w / (10 * kFps);
      *budget_w += steps[k].decision.budget_w / (10 * kFps);
      *best_w += (steps[k].true_power_w + kSavingW * steps[k].record.configuration[0]) / (10 * kFps);
    }
  };
  double budget_on = 0, drawn_on = 0, best_on = 0, budget_off = 0, drawn_off = 0, best_off = 0;
  run(true, &budget_on, &drawn_on, &best_on);
  run(false, &budget_off, &drawn_off, &best_off);
  // The runs draw the same frames: the best's power over the last 10 s is the same in both.
  REQUIRE(best_on == Approx(best_off).epsilon(1e-9));
  const double best_w = best_on, true_budget_w = best_w - 0.4 * 2 * kSavingW;
  INFO("the last 10 s: budget " << budget_on << " W, drawn " << drawn_on << " W (measured at their windows); "
                                << budget_off << " W, " << drawn_off << " W (not); 60 % of the true range "
                                << true_budget_w << " W");
  CHECK(std::abs(budget_on - true_budget_w) < 0.5);
  CHECK(std::abs(budget_on - true_budget_w) < std::abs(budget_off - true_budget_w));
  CHECK(drawn_on <= budget_on + kToleranceW);
  CHECK(drawn_on < best_w - 1.5);
}

TEST_CASE("exploring the cheapest: never when the model predicts savings, a full budget or feedback off",
          "[loop][extremes]") {
  const UnseenKnob knob(kUnseenKnob);
  auto explorations = [&](const char* budget, bool feedback, double saving_w) {
    GovernorSettings settings = power_budget(budget);
    settings.feedback.enabled = feedback;
    Governor governor(model::testing::synthetic_profile(), knob.space, ErrorTable(knob.space), settings);
    std::size_t n = 0;
    for (const Step& s : knob.run(governor, 20 * kFps, saving_w)) n += s.decision.event == Event::explore;
    return n;
  };
  CHECK(explorations("100%", true, 3.0) == 0);  // the best is admitted by definition
  CHECK(explorations("50%", false, 3.0) == 0);  // nothing would measure the cheapest's window
  CHECK(explorations("50%", true, 0.0) == 1);   // nothing to find, measured once all the same
  // A watts budget the best is predicted within: nothing is asked of the knobs.
  CHECK(explorations("1000W", true, 3.0) == 0);
  // The six-pass scene, whose counts show what every level saves: no exploration.
  GovernorSettings settings = power_budget("50%");
  App app(settings);
  std::size_t n = 0;
  for (const Step& s : app.run(20 * kFps)) n += s.decision.event == Event::explore;
  CHECK(n == 0);
}

TEST_CASE("a configuration predicted over the budget for a few frames is selected again at once", "[loop]") {
  // The camera at a quarter of the other tests' slowness: the scene's power drifts fast, and a
  // watts budget does not move with it. Waiting out select_frames (200 frames) after the scene
  // got heavier leaves more windows over the budget than selecting again once the model has
  // predicted the chosen configuration over it for 10 frames (the default).
  // Over three seeds: one run's windows move by a few with any change to what it draws.
  auto run = [](std::size_t reselect, std::size_t* early) {
    double share = 0.0;
    *early = 0;
    for (const unsigned seed : {7u, 11u, 13u}) {
      GovernorSettings settings = power_budget("50%");
      settings.reselect_over_budget_frames = reselect;
      // Both select again too, after a window over the budget.
      settings.feedback.enabled = false;
      settings.meter_windows = false;
      App app(settings, Configuration(6, 0), seed, 16);
      const std::vector<Step> steps = app.run(60 * kFps);
      std::uint64_t last = 0;
      for (const Step& s : steps) {
        if (s.decision.event != Event::select) continue;
        if (last && s.record.frame - last < settings.select_frames) ++*early;
        last = s.record.frame;
      }
      share += share_of_windows_within(app, steps, settings.power) / 3.0;
    }
    return share;
  };
  std::size_t early_on = 0, early_off = 0;
  const double on = run(10, &early_on), off = run(0, &early_off);
  INFO("share of 1-s windows within the budget: " << on << " selecting again, " << off << " every 200 frames");
  CHECK(early_off == 0);
  CHECK(early_on >= 1);
  CHECK(on > off);
}

TEST_CASE("measured power corrects what the model cannot see, and keeps windows within the budget",
          "[loop][feedback]") {
  // Every cheaper level draws 0.3 W more than the counts say (fixed costs the model does not
  // know, as a render scale's): open loop, the governor counts on savings that do not come;
  // the feedback measures them, corrects every configuration additively, keeps a margin of
  // the measured spread and selects again after a window over the budget.
  const auto unseen = [](const Configuration& c) {
    double w = 0.0;
    for (int level : c) w += 0.3 * level;
    return w;
  };
  auto run = [&](const char* budget, bool feedback, double* mean_excess) {
    GovernorSettings settings = power_budget(budget);
    settings.feedback.enabled = feedback;
    App app(settings, Configuration(6, 0), 7, 1 << 20,
            unseen);  // a still camera: the model's bias, not the scene's drift
    const std::vector<Step> steps = app.run(90 * kFps);
    // The metric of bench/governor/evaluate_budgets.py: a 1-s window's mean measured power
    // against the mean budget the governor gave.
    int windows = 0, within = 0;
    double excess = 0.0;
    for (std::size_t start = kConverged; start + kFps <= steps.size(); start += kFps) {
      double power = 0.0, limit = 0.0;
      for (std::size_t k = start; k < start + kFps; ++k) {
        power += steps[k].true_power_w / kFps;
        limit += steps[k].decision.budget_w / kFps;
      }
      ++windows;
      within += power <= limit;
      excess += std::max(0.0, power - limit);
    }
    *mean_excess = excess / windows;
    if (feedback) {
      CHECK(app.governor().feedback().windows() > 15);
      CHECK(app.governor().feedback().margin_w() > 0.0);
      CHECK(app.governor().feedback().margin_w() < 2.0);
    }
    return static_cast<double>(within) / windows;
  };
  // What the feedback cannot remove here is the temporal filter's passage through
  // intermediate configurations after each selection (a third of the run) and the frames'
  // 10 % jitter: the gain is in how far windows go over the budget.
  double total_on = 0.0, total_off = 0.0;
  for (const char* budget : {"40%", "50%", "60%"}) {
    double excess_on = 0.0, excess_off = 0.0;
    const double on = run(budget, true, &excess_on), off = run(budget, false, &excess_off);
    INFO("budget " << budget << ": 1-s windows within it " << on << " with feedback (mean excess " << excess_on
                   << " W), " << off << " open loop (" << excess_off << " W)");
    CHECK(on >= off - 0.05);
    total_on += excess_on;
    total_off += excess_off;
  }
  CHECK(total_on < 0.8 * total_off);
}

TEST_CASE("a calibrated range sets the bottom of a share of the range", "[loop][extremes]") {
  // The best and cheapest configurations' power from `glbudget calibrate --app`: the bottom of
  // the range is the best's power above P_m scaled by the cheapest's share of it, instead of
  // the model's prediction of the cheapest. A cheapest measured at the best's power leaves
  // nothing to save: 40 % is the best's power, and the first selection is of lower estimated
  // error than under the model's range; one at P_m puts 40 % below the model's range's, and
  // the first selection has the higher error.
  const double p_min = model::testing::synthetic_profile().p_min_w;
  struct Result {
    double first_budget_w = std::nan("");
    double error = std::nan("");  // of the first selection's target
  };
  auto run = [](std::optional<model::VariantTable::MeasuredRange> range) {
    GovernorSettings settings = power_budget("40%");
    settings.calibrated_range = range;
    App app(settings);
    const std::vector<Step> steps = app.run(20 * kFps);
    Result r;
    for (const Step& s : steps)
      if (s.decision.event == Event::select) {
        r.first_budget_w = s.decision.budget_w;
        r.error = app.governor().errors().estimate(s.target);
        break;
      }
    return r;
  };
  const Result none = run(std::nullopt);
  const Result flat = run(model::VariantTable::MeasuredRange{60.0, 60.0});
  const Result deep = run(model::VariantTable::MeasuredRange{60.0, p_min});
  INFO("first budgets: the model's range " << none.first_budget_w << " W, nothing to save " << flat.first_budget_w
                                           << " W, all saved " << deep.first_budget_w << " W");
  REQUIRE(std::isfinite(none.first_budget_w));
  CHECK(flat.first_budget_w > none.first_budget_w);
  CHECK(deep.first_budget_w < none.first_budget_w);
  CHECK(flat.error < none.error);
  CHECK(deep.error > none.error);
}

TEST_CASE("with each level's calibrated power, a combination is its levels' changes summed plus a held interaction",
          "[loop][feedback]") {
  // `glbudget calibrate --app` measured the best, every level alone and the cheapest (here the
  // truth at the path's first counts). `additive`: the selection's table is the best's
  // corrected prediction plus each level's change alone, with the feedback's terms, which are
  // additive too. `model`: the model's saturating curve makes the levels' changes interact.
  // `calibrated`: that interaction, scaled towards the measured cheapest and never beyond the
  // model's own; the synthetic truth has the model's curve, so most of it is kept.
  struct Result {
    double largest_gap_w = 0.0;  // from the levels' changes summed
    double cheapest_w = 0.0;     // predicted
    double share = 0.0;
  };
  const model::testing::HiddenModel hidden = model::testing::six_pass_hidden_model();
  const Configuration best(6, 0), cheapest = hidden.space.cheapest();
  auto run = [&](GovernorSettings::Interactions interactions) {
    model::testing::SceneGenerator scene(hidden, 0.0, 7);
    const Truth truth(hidden, scene.counts(0));
    GovernorSettings settings = power_budget("50%");
    settings.level_interactions = interactions;
    settings.calibrated_range = model::VariantTable::MeasuredRange{truth.power(best), truth.power(cheapest)};
    for (std::size_t i = 0; i < 6; ++i)
      for (int l = 1; l < static_cast<int>(hidden.space.passes()[i].levels.size()); ++l) {
        Configuration c = best;
        c[i] = l;
        settings.calibrated_powers.emplace_back(c, truth.power(c));
      }
    App app(settings);
    app.run(20 * kFps);
    REQUIRE(app.governor().selections() > 0);
    const Governor::SelectionTable table = app.governor().last_selection();
    const auto& power = *table.power_w;
    const model::ConfigurationSpace& space = app.governor().space();
    Result r;
    r.largest_gap_w = largest_gap_from_levels_summed(space, power);
    r.cheapest_w = power[space.index_of(cheapest)];
    r.share = app.governor().interaction_share();
    return r;
  };
  const Result additive = run(GovernorSettings::Interactions::additive);
  const Result own = run(GovernorSettings::Interactions::model);
  const Result calibrated = run(GovernorSettings::Interactions::calibrated);
  INFO("largest gap from the levels' changes summed: " << additive.largest_gap_w << " W additive, " << own.largest_gap_w
                                                       << " W the model's, " << calibrated.largest_gap_w
                                                       << " W calibrated (share " << calibrated.share << ")");
  CHECK(additive.largest_gap_w < 1e-9);
  CHECK(additive.share == 0.0);
  CHECK(own.largest_gap_w > 0.1);
  CHECK(own.share == 1.0);
  CHECK(calibrated.share > 0.5);
  CHECK(calibrated.share <= 1.0);
  CHECK(calibrated.largest_gap_w <= own.largest_gap_w + 1e-9);
  // The cheapest between the sum and the model's own, within what each run's own history moves
  // its table: the three runs draw and measure other configurations, and the feedback's terms
  // and the model's fit follow them (the paper's blend and the ordered transition, the same
  // runs otherwise, put the three 0.3-0.6 W apart in each direction).
  CHECK(calibrated.cheapest_w >= std::min(additive.cheapest_w, own.cheapest_w) - 0.75);
  CHECK(calibrated.cheapest_w <= std::max(additive.cheapest_w, own.cheapest_w) + 0.75);
}

TEST_CASE("scaled: the levels' changes summed, scaled so that the cheapest is predicted where it was measured",
          "[loop][feedback]") {
  // Levels whose savings overlap beyond the model's interaction: calibration measured the
  // cheapest with half the saving its levels' changes sum to (the demo's Hall: 17.7 W where they
  // sum to 26). `calibrated` keeps at most the model's own interaction and predicts the cheapest
  // far under its measurement, and every combination with it; `scaled` predicts the best plus the
  // summed changes times the share that puts the cheapest where it was measured.
  const model::testing::HiddenModel hidden = model::testing::six_pass_hidden_model();
  const Configuration best(6, 0), cheapest = hidden.space.cheapest();
  model::testing::SceneGenerator scene0(hidden, 0.0, 7);
  const Truth truth(hidden, scene0.counts(0));
  double summed_cheapest = truth.power(best);
  std::vector<std::pair<Configuration, double>> singles;
  for (std::size_t i = 0; i < 6; ++i)
    for (int l = 1; l < static_cast<int>(hidden.space.passes()[i].levels.size()); ++l) {
      Configuration c = best;
      c[i] = l;
      singles.emplace_back(c, truth.power(c));
      if (l + 1 == static_cast<int>(hidden.space.passes()[i].levels.size()))
        summed_cheapest += truth.power(c) - truth.power(best);
    }
  const double measured_cheapest = truth.power(best) - 0.5 * (truth.power(best) - summed_cheapest);
  REQUIRE(measured_cheapest > truth.power(cheapest) + 1.0);  // beyond what the model's curve gives
  struct Result {
    double cheapest_w = 0.0, best_w = 0.0, largest_gap_w = 0.0;
  };
  auto run = [&](GovernorSettings::Interactions interactions) {
    GovernorSettings settings = power_budget("50%");
    settings.level_interactions = interactions;
    settings.calibrated_range = model::VariantTable::MeasuredRange{truth.power(best), measured_cheapest};
    settings.calibrated_powers = singles;
    App app(settings);
    // Up to the first selection: the cheapest not yet measured by the run.
    Step last;
    for (int k = 0; k < 20 * kFps && app.governor().selections() == 0; ++k) last = app.step();
    REQUIRE(app.governor().selections() > 0);
    const Governor::SelectionTable table = app.governor().last_selection();
    const auto& power = *table.power_w;
    const model::ConfigurationSpace& space = app.governor().space();
    // The frame's own prediction, corrected, is the table's at the selection's frame.
    REQUIRE(std::isfinite(last.decision.predicted_w));
    CHECK(last.decision.predicted_w == Approx(power[space.index_of(last.record.configuration)]).margin(1e-6));
    Result r;
    r.largest_gap_w = largest_gap_from_levels_summed(space, power);
    r.cheapest_w = power[space.index_of(cheapest)];
    r.best_w = power[space.index_of(best)];
    return r;
  };
  const Result calibrated = run(GovernorSettings::Interactions::calibrated);
  const Result scaled = run(GovernorSettings::Interactions::scaled);
  INFO("measured cheapest " << measured_cheapest << " W (changes summed " << summed_cheapest << " W); predicted "
                            << calibrated.cheapest_w << " W calibrated, " << scaled.cheapest_w << " W scaled");
  CHECK(std::abs(scaled.cheapest_w - measured_cheapest) < 0.5);
  CHECK(calibrated.cheapest_w < measured_cheapest - 1.0);
  // One share for every configuration: the table is its own levels' changes summed.
  CHECK(scaled.largest_gap_w < 1e-9);
  CHECK(scaled.cheapest_w < scaled.best_w);
}

TEST_CASE("the range's top stays within best_band of the best's measured power above P_m", "[loop][feedback]") {
  // The app starts at its best and leaves it at the first selection; 5 s later the best's frames
  // have left the model's history (300 frames). A share's top is then the best's prediction
  // now plus its windows' residual, held within best_band of what those windows measured above
  // P_m: 0 holds it there, an infinite band leaves it to the prediction. The six-pass scene's
  // model is of the scene's own family, so its prediction is good here: the default band must
  // cost it little.
  const double p_min_w = model::testing::synthetic_profile().p_min_w;
  const Configuration best(6, 0);
  struct Result {
    double best_measured_w = 0.0;  // its frames' mean before the first selection
    double lowest_w = std::numeric_limits<double>::infinity(), highest_w = 0.0;
    double truth_gap_w = 0.0;  // the top's mean distance from the best's true power at the frame
    int selections = 0;
  };
  auto run = [&](double band) {
    GovernorSettings settings = power_budget("50%");
    settings.best_band = band;
    App app(settings);
    Result r;
    int at_best = 0;
    std::uint64_t seen = 0;
    for (int k = 0; k < 120 * kFps; ++k) {
      const Step s = app.step();
      if (app.governor().selections() == 0) {
        if (s.record.configuration == best && s.record.frame >= 1 * kFps) {
          r.best_measured_w += s.record.power_w;
          ++at_best;
        }
        continue;
      }
      const Governor::SelectionTable table = app.governor().last_selection();
      if (table.frame == seen || s.record.frame != table.frame) continue;
      seen = table.frame;
      if (s.record.frame < 10 * kFps) continue;  // the best's frames still in the history
      r.lowest_w = std::min(r.lowest_w, table.range_high_w);
      r.highest_w = std::max(r.highest_w, table.range_high_w);
      r.truth_gap_w += std::abs(table.range_high_w - Truth(app.hidden(), s.record.passes).power(best));
      ++r.selections;
    }
    REQUIRE(at_best > 0);
    r.best_measured_w /= at_best;
    if (r.selections > 0) r.truth_gap_w /= r.selections;
    return r;
  };
  const Result held = run(0.0), banded = run(0.1), free = run(std::numeric_limits<double>::infinity());
  const double above_w = held.best_measured_w - p_min_w;
  INFO("the best measured " << held.best_measured_w << " W before the first selection; the top from 10 s on, "
                            << "band 0: " << held.lowest_w << "-" << held.highest_w << " W (" << held.truth_gap_w
                            << " W from the truth on average), 0.1: " << banded.lowest_w << "-" << banded.highest_w
                            << " W (" << banded.truth_gap_w << " W), none: " << free.lowest_w << "-" << free.highest_w
                            << " W (" << free.truth_gap_w << " W)");
  REQUIRE(held.selections >= 10);
  REQUIRE(banded.selections >= 10);
  REQUIRE(free.selections >= 10);
  // Band 0: the windows' measurement, unmoved by the prediction (the windows leave the frames of
  // the transitions out; the frames' mean here keeps them).
  CHECK(held.highest_w - held.lowest_w < 1e-9);
  CHECK(std::abs(held.lowest_w - held.best_measured_w) < 0.3);
  // The default band: within 0.1 of the measurement above P_m, and as close to the truth as the
  // prediction alone, give or take the scene's noise.
  CHECK(banded.lowest_w >= p_min_w + 0.9 * above_w - 0.3);
  CHECK(banded.highest_w <= p_min_w + 1.1 * above_w + 0.3);
  CHECK(banded.truth_gap_w <= free.truth_gap_w + 0.2);
  // No band: the prediction moves it with the scene's counts.
  CHECK(free.highest_w - free.lowest_w > 0.1);
}

TEST_CASE("scaled: a level calibrated over the best is taken as no change, not a cost", "[loop][feedback]") {
  // The calibration's scatter put one pass's cheapest level 6 W over the best (the demo's
  // calibrations on the cpu estimate: up to 4.6 W). Taken as measured it would cancel 6 W of the
  // other levels' savings wherever it is summed, the cheapest's included.
  const model::testing::HiddenModel hidden = model::testing::six_pass_hidden_model();
  const Configuration best(6, 0), cheapest = hidden.space.cheapest();
  model::testing::SceneGenerator scene0(hidden, 0.0, 7);
  const Truth truth(hidden, scene0.counts(0));
  std::vector<std::pair<Configuration, double>> singles;
  double others_summed_w = 0.0;  // the other passes' cheapest levels' changes, summed
  Configuration wrong = best;
  wrong[1] = static_cast<int>(hidden.space.passes()[1].levels.size()) - 1;
  for (std::size_t i = 0; i < 6; ++i)
    for (int l = 1; l < static_cast<int>(hidden.space.passes()[i].levels.size()); ++l) {
      Configuration c = best;
      c[i] = l;
      const bool last = l + 1 == static_cast<int>(hidden.space.passes()[i].levels.size());
      singles.emplace_back(c, c == wrong ? truth.power(best) + 6.0 : truth.power(c));
      if (last && c != wrong) others_summed_w += truth.power(c) - truth.power(best);
    }
  GovernorSettings settings = power_budget("50%");
  settings.level_interactions = GovernorSettings::Interactions::scaled;
  settings.calibrated_range = model::VariantTable::MeasuredRange{truth.power(best), truth.power(cheapest)};
  settings.calibrated_powers = singles;
  App app(settings);
  for (int k = 0; k < 20 * kFps && app.governor().selections() == 0; ++k) app.step();
  REQUIRE(app.governor().selections() > 0);
  const auto& power = *app.governor().last_selection().power_w;
  const model::ConfigurationSpace& space = app.governor().space();
  const double best_w = power[space.index_of(best)], wrong_w = power[space.index_of(wrong)];
  const double cheapest_w = power[space.index_of(cheapest)];
  INFO("best " << best_w << " W, the level calibrated over it " << wrong_w << " W, the cheapest " << cheapest_w
               << " W (measured " << truth.power(cheapest) << " W; the other levels' changes sum to " << others_summed_w
               << " W)");
  CHECK(wrong_w <= best_w + 1e-9);
  CHECK(wrong_w == Approx(best_w).margin(0.5));
  CHECK(cheapest_w <= best_w + others_summed_w + 0.5);
}

TEST_CASE("power feedback: windows, residuals, the margin and the additive correction", "[loop][feedback]") {
  PowerFeedback feedback{FeedbackSettings{}};
  const Configuration a{0, 0}, b{2, 0};
  CHECK(feedback.bias(a) == 0.0);
  CHECK(feedback.margin_w() == 0.0);
  // One window at a: residual +1 W exactly (no scatter within), closed by the frame at 1 s.
  std::int64_t t = 0;
  std::optional<PowerFeedback::Window> closed;
  for (int k = 0; k <= 10; ++k, t += 100'000'000) closed = feedback.add(a, t, 11.0, 10.0);
  REQUIRE(closed);
  CHECK(closed->frames == 11);
  CHECK(closed->measured_w == Approx(11.0));
  CHECK(feedback.residual(a) == Approx(1.0));
  CHECK(feedback.bias(a) == Approx(1.0));
  // One configuration measured: an offset for all.
  CHECK(feedback.bias(Configuration{1, 2}) == Approx(1.0));
  // A second, -1 W, without scatter: the first pass's level 2 is 2 W cheaper than predicted,
  // for every configuration drawing it; a level never drawn keeps the offset.
  feedback.interrupt();
  for (int k = 0; k <= 10; ++k, t += 100'000'000) closed = feedback.add(b, t, 9.0, 10.0);
  REQUIRE(closed);
  CHECK(feedback.bias(b) == Approx(-1.0).margin(1e-3));
  CHECK(feedback.bias(Configuration{2, 2}) == Approx(-1.0).margin(1e-3));
  CHECK(feedback.bias(Configuration{1, 0}) == Approx(1.0).margin(1e-3));
  // a again, 0.5 W off its residual: the spread of windows is 0.5 W, and with a prior of
  // 5 % of ~10.5 W a 2-W term measured once is shrunk towards the offset.
  feedback.interrupt();
  for (int k = 0; k <= 10; ++k, t += 100'000'000) closed = feedback.add(a, t, 11.5, 10.0);
  REQUIRE(closed);
  CHECK(feedback.spread_w() == Approx(0.5));
  CHECK(feedback.margin_w() == Approx(1.6449 * 0.5).epsilon(1e-3));
  CHECK(feedback.residual(a) == Approx(1.25));
  CHECK(feedback.bias(b) < -0.05);
  CHECK(feedback.bias(b) > -1.0);
  CHECK(feedback.bias(a) > feedback.bias(b));
  std::vector<double> predicted(9, 10.0);
  const model::ConfigurationSpace space({{"p", {{}, {}, {}}, {}}, {"q", {{}, {}, {}}, {}}});
  feedback.correct(space, predicted);
  CHECK(predicted[space.index_of(b)] == Approx(10.0 + feedback.bias(b)));
  CHECK(predicted[space.index_of(a)] == Approx(10.0 + feedback.bias(a)));
  // NaN power is no frame; time going back restarts the window; off: nothing.
  CHECK_FALSE(feedback.add(a, t, std::nan(""), 10.0));
  CHECK_FALSE(feedback.add(a, t - 5'000'000'000, 10.0, 10.0));
  PowerFeedback off(FeedbackSettings{false});
  for (int k = 0; k <= 10; ++k) CHECK_FALSE(off.add(a, k * 100'000'000LL, 11.0, 10.0));
  CHECK(off.bias(a) == 0.0);
}

TEST_CASE("power feedback: a prior per level corrects before any window, and windows outweigh it", "[loop][feedback]") {
  PowerFeedback feedback{FeedbackSettings{}};
  const Configuration best{0, 0}, shadows{0, 2}, both{1, 2};
  feedback.set_prior({{0.0, 3.0}, {0.0, 0.0, -5.0}});
  CHECK(feedback.bias(best) == Approx(0.0).margin(1e-9));
  CHECK(feedback.bias(shadows) == Approx(-5.0));
  CHECK(feedback.bias(both) == Approx(-2.0));  // additive, as the terms are
  // Windows at the best (as the governor measures first) predicted right, then at the shadows
  // level saying it saves 1 W less than predicted, not 5 more: the level's term follows them.
  std::int64_t t = 0;
  for (int w = 0; w < 4; ++w)
    for (int k = 0; k < 10; ++k, t += 100'000'000) feedback.add(best, t, 30.0 + 0.1 * (k % 2), 30.05);
  for (int w = 0; w < 8; ++w)
    for (int k = 0; k < 10; ++k, t += 100'000'000) feedback.add(shadows, t, 29.0 + 0.1 * (k % 2), 30.05);
  CHECK(feedback.measured(shadows));
  CHECK(feedback.bias(shadows) == Approx(-1.0).margin(0.2));
  CHECK(feedback.bias(Configuration{1, 0}) == Approx(3.0).margin(0.5));  // a level never drawn keeps its prior
}

TEST_CASE("power feedback: a refit moves a residual by its change, and the open window with it", "[loop][feedback]") {
  PowerFeedback feedback{FeedbackSettings{}};
  const Configuration a{0, 0}, b{1, 0};
  std::int64_t t = 0;
  // Two windows at a, residual +1 W; one at b, residual -0.5 W.
  for (int w = 0; w < 2; ++w)
    for (int k = 0; k <= 10; ++k, t += 100'000'000) feedback.add(a, t, 11.0, 10.0);
  feedback.interrupt();
  for (int k = 0; k <= 10; ++k, t += 100'000'000) feedback.add(b, t, 9.5, 10.0);
  feedback.interrupt();
  const double bias_a = feedback.bias(a), bias_b = feedback.bias(b);
  // Half a window at a, then a refit predicts a 2 W higher; b is left alone.
  for (int k = 0; k < 5; ++k, t += 100'000'000) feedback.add(a, t, 11.0, 10.0);
  feedback.rebase(a, 2.0);
  CHECK(feedback.residual(a) == Approx(-1.0));
  CHECK(feedback.residual(b) == Approx(-0.5));
  // What is measured at a is predicted as before: the new prediction plus the moved bias.
  CHECK(12.0 + feedback.bias(a) == Approx(10.0 + bias_a).margin(0.05));
  // b keeps its own residual; a configuration never measured follows the offset, which moved.
  CHECK(feedback.bias(b) == Approx(bias_b).margin(0.05));
  CHECK(feedback.bias(Configuration{0, 1}) == Approx(-1.0).margin(0.05));
  // The open window goes on: its first half was predicted at 10 W, now counted at 12 W like
  // the frames that follow, and nothing within it scattered.
  std::optional<PowerFeedback::Window> closed;
  for (int k = 0; k < 6; ++k, t += 100'000'000) closed = feedback.add(a, t, 11.0, 12.0);
  REQUIRE(closed);
  CHECK(closed->frames == 11);
  CHECK(closed->predicted_w == Approx(12.0));
  CHECK(feedback.residual(a) == Approx(-1.0));
  CHECK(feedback.spread_w() == Approx(0.0).margin(1e-9));
  // A NaN change for the open window's configuration drops it, as does a change of another
  // configuration's (the window then is not the drawn configuration's); off: nothing moves.
  for (int k = 0; k < 5; ++k, t += 100'000'000) feedback.add(a, t, 11.0, 12.0);
  feedback.rebase(a, std::nan(""));
  CHECK(feedback.residual(a) == Approx(-1.0));
  for (int k = 0; k < 6; ++k, t += 100'000'000) closed = feedback.add(a, t, 11.0, 12.0);
  CHECK_FALSE(closed);
  for (int k = 0; k < 5; ++k, t += 100'000'000) feedback.add(a, t, 11.0, 12.0);
  feedback.rebase(Configuration{2, 2}, 1.0);
  CHECK(feedback.residual(a) == Approx(-1.0));
  for (int k = 0; k < 6; ++k, t += 100'000'000) closed = feedback.add(a, t, 11.0, 12.0);
  CHECK_FALSE(closed);
  PowerFeedback off(FeedbackSettings{false});
  off.rebase(a, 1.0);
  CHECK(off.bias(a) == 0.0);
}

TEST_CASE("power feedback: the frames it takes and the windows it opens are counted", "[loop][feedback]") {
  PowerFeedback feedback{FeedbackSettings{}};
  const Configuration a{0, 0}, b{1, 0};
  std::int64_t t = 0;
  feedback.add(a, t, 10.0, 10.0);
  CHECK(feedback.frames_taken() == 1);
  CHECK(feedback.windows_opened() == 1);
  feedback.add(a, t += 100'000'000, std::nan(""), 10.0);  // not taken: no power
  CHECK(feedback.frames_taken() == 1);
  // A one-frame window replaced by another configuration's: a new window, though both hold one
  // frame.
  feedback.add(b, t += 100'000'000, 10.0, 10.0);
  CHECK(feedback.frames_taken() == 2);
  CHECK(feedback.windows_opened() == 2);
  feedback.add(b, t -= 50'000'000, 10.0, 10.0);  // time went back: a new window too
  CHECK(feedback.windows_opened() == 3);
  std::optional<PowerFeedback::Window> closed;
  for (int k = 0; k <= 10 && !closed; ++k) closed = feedback.add(b, t += 100'000'000, 10.0, 10.0);
  REQUIRE(closed);
  CHECK(feedback.windows_opened() == 3);
  CHECK(feedback.frames_taken() == 3 + closed->frames - 1);
}

TEST_CASE("power feedback: a first window's surprise is kept for the configurations not measured, and fades",
          "[loop][feedback]") {
  FeedbackSettings no_floor;
  no_floor.surprise_floor_share = 0.0;  // the surprises alone (the floor: the next test)
  PowerFeedback feedback{no_floor};
  const Configuration a{0, 0}, b{1, 0};
  std::int64_t t = 0;
  auto window = [&](const Configuration& c, double measured, double predicted) {
    feedback.interrupt();
    std::optional<PowerFeedback::Window> closed;
    for (int k = 0; k <= 10; ++k, t += 100'000'000) closed = feedback.add(c, t, measured, predicted);
    REQUIRE(closed);
  };
  // The run's first window is no surprise: nothing was counted on before it.
  window(a, 10.0, 10.0);
  CHECK(feedback.unmeasured_margin_w() == 0.0);
  // b was counted on at 10 W (the offset, 0) and drew 13 W.
  window(b, 13.0, 10.0);
  constexpr double z = 1.6449;
  CHECK(feedback.margin_w() == Approx(0.0).margin(1e-9));
  CHECK(feedback.unmeasured_margin_w() == Approx(z * 3.0).epsilon(1e-3));
  const std::vector<Configuration> measured = feedback.measured_configurations();
  CHECK(measured == std::vector<Configuration>{a, b});
  // Windows at measured configurations, no new surprise: it fades, a thirtieth of its square
  // a window.
  for (int w = 0; w < 30; ++w) window(a, 10.0, 10.0);
  CHECK(feedback.unmeasured_margin_w() == Approx(z * 3.0 * std::pow(1.0 - 1.0 / 30.0, 15.0)).epsilon(1e-3));
  // A configuration predicted right (or over its power) on its first window: the mean of the
  // two surprises' squares.
  const double before = feedback.unmeasured_margin_w();
  window(Configuration{0, 1}, 8.0 + feedback.bias(Configuration{0, 1}), 10.0);
  CHECK(feedback.unmeasured_margin_w() < before);
  CHECK(feedback.unmeasured_margin_w() == Approx(before * std::sqrt((1.0 - 1.0 / 30.0) * 0.5)).epsilon(1e-3));
  // Off: 0.
  FeedbackSettings off;
  off.guard_unmeasured = false;
  PowerFeedback unguarded{off};
  t = 0;
  for (const auto& [c, m] : {std::pair{a, 10.0}, {b, 13.0}}) {
    unguarded.interrupt();
    for (int k = 0; k <= 10; ++k, t += 100'000'000) unguarded.add(c, t, m, 10.0);
  }
  CHECK(unguarded.unmeasured_margin_w() == 0.0);
}

TEST_CASE("power feedback: the typical surprise is at least its floor's share of the power", "[loop][feedback]") {
  FeedbackSettings settings;
  settings.surprise_floor_share = 0.02;
  PowerFeedback feedback{settings};
  const Configuration a{0, 0}, b{1, 0}, c{0, 1};
  std::int64_t t = 0;
  // Windows whose frames scatter by +-s about `measured`, so that the spread is not 0.
  auto window = [&](const Configuration& at, double measured, double predicted, double s) {
    feedback.interrupt();
    std::optional<PowerFeedback::Window> closed;
    for (int k = 0; k <= 10; ++k, t += 100'000'000)
      closed = feedback.add(at, t, measured + (k % 2 ? s : -s), predicted);
    REQUIRE(closed);
  };
  constexpr double z = 1.6449;
  CHECK(feedback.typical_surprise_w() == 0.0);  // no window yet: nothing to take a share of
  CHECK(feedback.unmeasured_margin_w() == 0.0);
  // One window at 20 W, whose frames scatter little: the floor, 0.4 W, is the typical surprise,
  // before any configuration measured after the first has surprised.
  window(a, 20.0, 20.0, 0.05);
  CHECK(feedback.surprises() == 0);
  CHECK(feedback.typical_surprise_w() == Approx(0.4).epsilon(1e-3));
  CHECK(feedback.unmeasured_margin_w() ==
        Approx(z * feedback.typical_surprise_w() - feedback.margin_w()).epsilon(1e-3));
  CHECK(feedback.unmeasured_margin_w() > 0.5);
  // Two configurations that met their predictions: still the floor, not 0.
  window(b, 20.0 + feedback.bias(b), 20.0, 0.05);
  window(c, 20.0 + feedback.bias(c), 20.0, 0.05);
  CHECK(feedback.surprises() == 2);
  CHECK(feedback.typical_surprise_w() == Approx(0.4).epsilon(0.02));
  // A surprise beyond the floor is taken as it is.
  window(Configuration{1, 1}, 20.0 + feedback.bias(Configuration{1, 1}) + 3.0, 20.0, 0.05);
  CHECK(feedback.typical_surprise_w() > 1.0);
  // Where the spread's margin already covers z times the floor, nothing is added.
  PowerFeedback noisy{settings};
  t = 0;
  for (int w = 0; w < 3; ++w) {
    noisy.interrupt();
    for (int k = 0; k <= 10; ++k, t += 100'000'000) noisy.add(a, t, (w % 2 ? 23.0 : 17.0), 20.0);
  }
  CHECK(noisy.margin_w() > z * 0.4);
  CHECK(noisy.unmeasured_margin_w() == 0.0);
  // 0: no floor, as before it.
  FeedbackSettings off = settings;
  off.surprise_floor_share = 0.0;
  PowerFeedback unfloored{off};
  t = 0;
  for (int k = 0; k <= 10; ++k, t += 100'000'000) unfloored.add(a, t, 20.0, 20.0);
  CHECK(unfloored.typical_surprise_w() == 0.0);
  CHECK(unfloored.unmeasured_margin_w() == 0.0);
}

// A governed run's 1-s windows after convergence: how many measured within their budget, and,
// of those drawn in one configuration, how many were that configuration's first and how many of
// those went over.
struct FirstWindows {
  int windows = 0, within = 0, firsts = 0, first_over = 0;
  int mixed = 0, mixed_over = 0;  // windows drawing more than one configuration (a transition)
  double share_within() const { return windows ? static_cast<double>(within) / windows : 0.0; }
  FirstWindows& operator+=(const FirstWindows& other) {
    windows += other.windows;
    within += other.within;
    firsts += other.firsts;
    first_over += other.first_over;
    mixed += other.mixed;
    mixed_over += other.mixed_over;
    return *this;
  }
};

FirstWindows first_windows(const std::vector<Step>& steps) {
  FirstWindows counts;
  std::set<Configuration> seen;
  for (std::size_t start = kConverged; start + kFps <= steps.size(); start += kFps) {
    const Configuration& c = steps[start].record.configuration;
    bool one = true;
    double power = 0.0, limit = 0.0;
    for (std::size_t k = start; k < start + kFps; ++k) {
      one = one && steps[k].record.configuration == c;
      power += steps[k].true_power_w / kFps;
      limit += steps[k].decision.budget_w / kFps;
    }
    ++counts.windows;
    counts.within += power <= limit;
    counts.mixed += !one;
    counts.mixed_over += !one && power > limit;
    if (!one) continue;
    const bool first = seen.insert(c).second;
    counts.firsts += first;
    counts.first_over += first && power > limit;
  }
  return counts;
}

TEST_CASE("configurations never measured are kept further under the budget once one surprised", "[loop][feedback]") {
  // A cost the additive correction cannot learn from neighbours: the cheaper shadows draw 4 W
  // more than the counts say, but only at full resolution (a level whose saving depends on
  // another's). Each configuration combining them is predicted that much too cheap until a
  // window measures it; after the first such surprise, the others not measured keep a margin
  // of it, so fewer first windows go over the budget. Measured without the range's top held
  // near its measurement (best_band), which moves both runs' paths here: with bands of 0.1, 0.15,
  // 0.2 and 0.3 the guarded runs kept 0.71, 0.82, 0.82 and 0.80 of their windows and the
  // unguarded 0.71, 0.77, 0.67 and 0.71 (without a band 0.80 and 0.71). The guard is what this
  // compares.
  const auto unseen = [](const Configuration& c) { return c[0] == 0 && c[3] > 0 ? 4.0 : 0.0; };
  auto run = [&](const char* budget, bool guard, int* first_over, int* firsts) {
    GovernorSettings settings = power_budget(budget);
    settings.feedback.guard_unmeasured = guard;
    settings.best_band = std::numeric_limits<double>::infinity();
    App app(settings, Configuration(6, 0), 11, 64, unseen);
    const FirstWindows counts = first_windows(app.run(120 * kFps));
    *firsts += counts.firsts;
    *first_over += counts.first_over;
    return counts.share_within();
  };
  int over_on = 0, over_off = 0, firsts_on = 0, firsts_off = 0;
  double share_on = 0.0, share_off = 0.0;
  for (const char* budget : {"40%", "50%", "60%"}) {
    share_on += run(budget, true, &over_on, &firsts_on) / 3.0;
    share_off += run(budget, false, &over_off, &firsts_off) / 3.0;
  }
  INFO("first windows of a configuration over the budget: "
       << over_on << " of " << firsts_on << " guarded, " << over_off << " of " << firsts_off
       << " not; windows within it " << share_on << " against " << share_off);
  CHECK(over_off >= 3);
  CHECK(over_on <= 0.7 * over_off);
  CHECK(share_on >= share_off + 0.05);
}

TEST_CASE("a surprise floor keeps the first surprise's window under the budget", "[loop][feedback]") {
  // As the demo's Sponza at 40 % (run G): configurations never measured meet their predictions
  // until one draws 1.5 W (3 % of the scene's power) more than its levels say. Without the
  // floor nothing has surprised before it, and its first window goes over; the floor's share
  // of the power keeps that much room for any configuration never measured.
  const auto unseen = [](const Configuration& c) { return c[1] > 0 && c[4] > 0 ? 1.5 : 0.0; };
  auto run = [&](double floor, FirstWindows* total) {
    for (const char* budget : {"40%", "50%", "60%"})
      for (const unsigned seed : {7u, 11u, 13u}) {
        GovernorSettings settings = power_budget(budget);
        settings.feedback.surprise_floor_share = floor;
        App app(settings, Configuration(6, 0), seed, 64, unseen);
        *total += first_windows(app.run(60 * kFps));
      }
  };
  FirstWindows on, off;
  run(0.02, &on);
  run(0.0, &off);
  INFO("first windows of a configuration over the budget: "
       << on.first_over << " of " << on.firsts << " floored, " << off.first_over << " of " << off.firsts
       << " not; windows within it " << on.share_within() << " against " << off.share_within());
  CHECK(off.first_over >= 3);
  CHECK(on.first_over <= 0.5 * off.first_over);
  CHECK(on.share_within() >= off.share_within());
}

TEST_CASE("a transition that takes its savings first keeps its windows within the budget", "[loop]") {
  // The paper's blend moves every pass at once, a level at a time, in the order of its levels:
  // from 1:2:1:1:1:0 to 1:0:2:1:2:2 it drew 1:1:1:1:1:1, dearer than both ends, and the demo's
  // Sponza at 40 % went over the budget in the windows holding such transitions. Taken cheapest
  // first (at the blend's moments), the steps that save come before those that spend. Three
  // scenes: predictions that hold; two lowered passes together drawing 1.5 W more than their
  // levels say (which the order cannot know); every lowered level drawing 0.6 W more than the
  // model says, so that the knobs save almost nothing. Three budgets and thirty seeds each: one
  // run's windows move by a few with any change to what it draws.
  enum class Scene { holds, interaction, no_saving };
  const auto run = [](bool ordered, Scene scene, FirstWindows* total) {
    const auto unseen = [scene](const Configuration& c) {
      if (scene == Scene::interaction) return c[1] > 0 && c[4] > 0 ? 1.5 : 0.0;
      double w = 0.0;
      if (scene == Scene::no_saving)
        for (const int level : c) w += 0.6 * level;
      return w;
    };
    for (const char* budget : {"40%", "50%", "60%"})
      for (unsigned seed = 1; seed <= 30; ++seed) {
        GovernorSettings settings = power_budget(budget);
        settings.ordered_transition = ordered;
        App app(settings, Configuration(6, 0), seed, 64, unseen);
        *total += first_windows(app.run(60 * kFps));
      }
  };
  const auto over_rate = [](const FirstWindows& w) { return static_cast<double>(w.mixed_over) / w.mixed; };
  for (const Scene scene : {Scene::holds, Scene::interaction, Scene::no_saving}) {
    FirstWindows ordered, blended;
    run(true, scene, &ordered);
    run(false, scene, &blended);
    INFO("scene " << static_cast<int>(scene) << ": windows holding a transition over the budget " << ordered.mixed_over
                  << " of " << ordered.mixed << " ordered, " << blended.mixed_over << " of " << blended.mixed
                  << " blended; all windows within it " << ordered.share_within() << " against "
                  << blended.share_within());
    // The windows a user's meter finds over the budget: fewer in all. Per window holding a
    // transition, fewer where the knobs save (the runs make as many transitions as their
    // selections differ, and the blend's runs make twice as many where they do not).
    CHECK(blended.mixed_over >= 50);
    CHECK(ordered.mixed_over < 0.75 * blended.mixed_over);
    if (scene != Scene::no_saving) CHECK(over_rate(ordered) < 0.75 * over_rate(blended));
    CHECK(ordered.share_within() > blended.share_within());
  }
}

TEST_CASE("the first selection counts on part of an unmeasured configuration's predicted saving", "[loop][feedback]") {
  // Every configuration saves a fifth less than the counts say, as on the demo's scenes, where a
  // model fitted on the starting configuration's frames alone overstated the savings of the
  // first selection (it realised 0.38-1.5 of them, median 0.87). Until a second configuration
  // is measured nothing shows that; the first configuration selected draws over the budget
  // unless the selection counts on less of the saving.
  const HiddenModel hidden = model::testing::six_pass_hidden_model();
  SceneGenerator scene(hidden, kNoiseW, 7);
  const Truth start(hidden, scene.sample(0, Configuration(6, 0)).passes);
  const double best_w = start.power(Configuration(6, 0));
  const auto unseen = [&](const Configuration& c) { return 0.2 * (best_w - start.power(c)); };
  // Watts the first configuration selected drew over the budget, on average from when the
  // transition arrived there to the next selection (0 where the first choice was to explore
  // the cheapest, which measures a configuration first); and its estimated error.
  auto first_excess = [&](const char* budget, unsigned seed, double discount, double* error, int* runs) {
    GovernorSettings settings = power_budget(budget);
    settings.feedback.first_saving_discount = discount;
    // The discount alone: the surprise floor also keeps these first windows under the budget.
    settings.feedback.surprise_floor_share = 0.0;
    App app(settings, Configuration(6, 0), seed, 64, unseen);
    const std::vector<Step> steps = app.run(20 * kFps);
    std::size_t first = 0, next = steps.size();
    for (std::size_t k = 0; k < steps.size() && next == steps.size(); ++k) {
      if (steps[k].decision.event == Event::explore && !first) return 0.0;
      if (steps[k].decision.event != Event::select) continue;
      if (!first)
        first = k;
      else
        next = k;
    }
    REQUIRE(first > 0);
    const Configuration& target = steps[first].target;
    double power = 0.0, limit = 0.0;
    int frames = 0;
    for (std::size_t k = first; k < next; ++k)
      if (steps[k].record.configuration == target) {
        power += steps[k].true_power_w;
        limit += steps[k].decision.budget_w;
        ++frames;
      }
    REQUIRE(frames > 0);
    *error += app.governor().errors().estimate(target);
    ++*runs;
    return std::max(0.0, (power - limit) / frames);
  };
  double excess_on = 0.0, excess_off = 0.0, error_on = 0.0, error_off = 0.0;
  int runs_on = 0, runs_off = 0;
  for (const char* budget : {"40%", "50%", "60%"})
    for (const unsigned seed : {7u, 13u, 17u, 19u, 23u}) {
      excess_on += first_excess(budget, seed, 0.25, &error_on, &runs_on);
      excess_off += first_excess(budget, seed, 0.0, &error_off, &runs_off);
    }
  INFO("the first configurations' watts over the budget, summed over "
       << runs_on << " and " << runs_off << " runs: " << excess_on << " discounted, " << excess_off
       << " not; their mean estimated error " << error_on / runs_on << " against " << error_off / runs_off);
  REQUIRE(runs_on >= 10);
  REQUIRE(runs_off >= 10);
  CHECK(excess_off >= 2.0);
  CHECK(excess_on <= 0.25 * excess_off);
  CHECK(error_on / runs_on > error_off / runs_off);  // the price: the first configuration shows more error
}

TEST_CASE("a refit leaves the corrected prediction of the configuration drawn where its windows measured it",
          "[loop][feedback]") {
  // Costs the counts do not explain (every cheaper level 0.6 W more): each refit over the
  // recent configurations explains them differently, and moves the prediction of the one being
  // drawn, which its measured residual had corrected. Moved by as much, the residual keeps the
  // corrected prediction where it was.
  const auto unseen = [](const Configuration& c) {
    double w = 0.0;
    for (int level : c) w += 0.6 * level;
    return w;
  };
  // Over three seeds: which refits come in one configuration follows what each run draws.
  auto run = [&](bool rebase, double* jump, double* error) {
    int refits = 0, frames = 0;
    for (const unsigned seed : {7u, 11u, 13u}) {
      GovernorSettings settings = power_budget("50%");
      settings.feedback.rebase_on_refit = rebase;
      settings.feedback.surprise_floor_share = 0.0;  // fewer moves, fewer refits in one configuration
      // The refits that move a prediction most are those whose history has forgotten the
      // configurations the run left: remembering them (run_time_model.hpp, the default) leaves
      // steps of 0.6 W here without the rebase, against 1.0 W forgotten.
      settings.history.remembered_frames = 0;
      App app(settings, Configuration(6, 0), seed, 64, unseen);
      const std::vector<Step> steps = app.run(90 * kFps);
      // The step: the mean prediction of the 10 frames after the refit against the 10 before
      // (the frames' 10 % jitter in counts averaged out), all in one configuration.
      constexpr std::size_t kSpan = 10;
      for (std::size_t k = kConverged; k + kSpan < steps.size(); ++k) {
        const Step& s = steps[k];
        if (std::isfinite(s.decision.predicted_w)) {
          *error += std::pow(s.decision.predicted_w - s.true_power_w, 2);
          ++frames;
        }
        if (s.decision.event != Event::refit) continue;
        double before = 0.0, after = 0.0;
        bool one = true;
        for (std::size_t j = 1; j <= kSpan; ++j) {
          one = one && steps[k - j].record.configuration == s.record.configuration &&
                steps[k + j].record.configuration == s.record.configuration;
          before += steps[k - j].decision.predicted_w / kSpan;
          after += steps[k + j].decision.predicted_w / kSpan;
        }
        if (!one) continue;
        *jump += std::abs(after - before);
        ++refits;
      }
    }
    REQUIRE(refits >= 15);
    *jump /= refits;
    *error = std::sqrt(*error / frames);
  };
  double jump_on = 0.0, jump_off = 0.0, error_on = 0.0, error_off = 0.0;
  run(true, &jump_on, &error_on);
  run(false, &jump_off, &error_off);
  INFO("mean step of the corrected prediction at a refit "
       << jump_on << " W moved, " << jump_off << " W not; prediction error " << error_on << " W against " << error_off
       << " W");
  // Over the three runs: 0.54 W moved against 0.69 W not, with the ordered transition (the
  // default); 0.41 W against 0.91 W with the paper's blend, whose runs refit in other places.
  // The rebase takes less of the step off here than it did under the blend (a fifth against
  // more than half), and the prediction error with it 0.72 W against 0.54 W: in this scene,
  // whose knobs save almost nothing, the ordered runs measured fewer configurations.
  CHECK(jump_on < 0.8 * jump_off);
  CHECK(error_on < 0.9 * error_off);
}

TEST_CASE("power feedback: a measured configuration's correction follows its own windows where the terms cannot",
          "[loop][feedback]") {
  // Two passes whose cheaper levels each cost what the model predicts, alone; drawn together
  // they draw 3 W more (a saving that depends on the other pass's level, as Sponza's shadow
  // map at a scaled resolution). No offset and terms explain all four residuals: the additive
  // fit puts (1, 1) at about 2.25 W and its neighbours 0.75 W off. Its own windows say 3 W.
  const Configuration best{0, 0}, first{1, 0}, second{0, 1}, both{1, 1};
  auto measure = [](PowerFeedback& feedback, std::int64_t& t, const Configuration& c, double residual_w, int windows,
                    double scatter_w) {
    for (int w = 0; w < windows; ++w) {
      const double r = residual_w + (w % 2 ? scatter_w : -scatter_w);
      for (int k = 0; k <= 10; ++k, t += 100'000'000) feedback.add(c, t, 20.0 + r, 20.0);
      feedback.interrupt();
    }
  };
  auto run = [&](bool own, double scatter_w) {
    FeedbackSettings settings;
    settings.own_residuals = own;
    PowerFeedback feedback{settings};
    std::int64_t t = 0;
    for (const Configuration& c : {best, first, second}) measure(feedback, t, c, 0.0, 4, scatter_w);
    measure(feedback, t, both, 3.0, 4, scatter_w);
    return feedback;
  };
  const PowerFeedback own = run(true, 0.2), fit = run(false, 0.2);
  INFO("(1, 1): own " << own.bias(both) << " W, fit alone " << fit.bias(both) << " W; spread " << own.spread_w());
  CHECK(fit.bias(both) < 2.5);
  CHECK(own.bias(both) == Approx(3.0).margin(0.3));
  CHECK(std::abs(own.bias(best)) < 0.3);
  CHECK(std::abs(own.bias(first)) < 0.3);
  CHECK(own.fitted_bias(both) == Approx(fit.bias(both)));
  // A configuration never measured is the fit's, with or without.
  CHECK(own.bias(Configuration{2, 1}) == Approx(fit.bias(Configuration{2, 1})));
  // Windows scattering far beyond the prior's scale (1 W of 20 W) leave it to the fit: one
  // window is not believed over it.
  FeedbackSettings own_settings;
  own_settings.own_residuals = true;
  PowerFeedback noisy{own_settings};
  std::int64_t t = 0;
  for (const Configuration& c : {best, first, second}) measure(noisy, t, c, 0.0, 4, 4.0);
  measure(noisy, t, both, 3.0, 1, 4.0);
  INFO("noisy: spread " << noisy.spread_w() << ", residual " << noisy.residual(both) << ", fit "
                        << noisy.fitted_bias(both) << ", bias " << noisy.bias(both));
  CHECK(noisy.spread_w() > 3.0);
  CHECK(std::abs(noisy.bias(both) - noisy.fitted_bias(both)) <
        0.1 * std::abs(noisy.residual(both) - noisy.fitted_bias(both)));
}
