// The GLBUDGET_* environment variables the shim reads. Parsed once, at the first
// make-current (never in processes that do not use GL). Bad values: one `glbudget:` line
// on stderr and the default.
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "glbudget/loop/level_interactions.hpp"

namespace glbudget {

struct Options {
  std::string log_path;  // GLBUDGET_LOG: per-frame CSV; empty: no log
  double fps = 0;        // GLBUDGET_FPS: pace swaps to this rate; 0: no pacing
  std::string dump_dir;  // GLBUDGET_DUMP: shader/program dumps (turns instrumentation on)
  // GLBUDGET_INSTRUMENT=1: count executed instructions and texel accesses per program. A
  // measurement mode (it perturbs timing): off unless asked for, or implied by GLBUDGET_DUMP.
  bool instrument = false;
  std::string config_path;  // GLBUDGET_CONFIG: the variant manifest
  // GLBUDGET_COSTS: the variant table `glbudget calibrate --app` measured (empty: the default
  // path by executable name; "off": none).
  std::string costs_path;
  std::string force;           // GLBUDGET_FORCE: levels per pass ("1,0,2"), or several separated by ';'
  uint64_t force_every = 0;    // GLBUDGET_FORCE_EVERY: frames per configuration of a GLBUDGET_FORCE list
  std::string power;           // GLBUDGET_POWER: "40%", "35W" (parsed by the governor)
  std::string error;           // GLBUDGET_ERROR: the dual problem's error budget
  size_t select_frames = 200;  // GLBUDGET_SELECT_FRAMES: frames between selections
  double transition_s = 2.0;   // GLBUDGET_TRANSITION_S: the temporal filter's length
  // GLBUDGET_PROBE_PERIOD: frames between quality-probe frames (apply/probes.hpp); -1: not given
  // (10 when governing, else none); 0: none.
  int64_t probe_period = -1;
  std::string dump_probes;  // GLBUDGET_DUMP_PROBES: probe images as PPM files here
  int probe_scale = 0;      // GLBUDGET_PROBE_SCALE: SSIM at 1, 2 or 4 (0: Wang's rule for the size)
  // GLBUDGET_PROBE_SSIM: where probe frames are compared (apply/probe_ssim.hpp).
  enum class ProbeSsim { kAuto, kGpu, kCpu } probe_ssim = ProbeSsim::kAuto;
  // GLBUDGET_PROBE_LEVELS=all: probe frames take every level below the best of each pass in
  // turn, not only its cheapest (`glbudget calibrate --app` measures the ratios k so).
  bool probe_every_level = false;
  // GLBUDGET_PROBE_ORDER=weighted: once every pass is probed, probes take the pass of largest
  // error × age (loop/probe_order.hpp) rather than the passes in turn.
  bool probe_order_weighted = false;
  // GLBUDGET_PROBE_FOLLOW=0: every probe stream draws the whole frame, rather than starting at
  // the first call it draws differently from the app or from stream s0 (apply/probes.hpp).
  bool probe_follow = true;
  // GLBUDGET_PROBE_SWEEP (on by default under a budget; 0: the passes in turn, one a probe frame): once every
  // pass in the scene is probed, a settled probe frame probes all of them at once (s0 drawn once
  // for all), just before each of the governor's selections and at least every
  // GLBUDGET_PROBE_MAX_AGE_S (apply/probes.cpp, sweep_due), or as many at a time as the governor
  // finds room for under the budget (loop/governor.hpp, probe_streams_fit)
  bool probe_sweep = true;
  // GLBUDGET_PROBE_SWEEP was set (to 1: sweeps without a budget too, the probes' period then
  // being the user's; unset, sweeps only where the governor steers: apply/probes.cpp)
  bool probe_sweep_set = false;
  // GLBUDGET_PROBE_PASSES=N: where settled probe frames sweep, at most N passes in one (each pass
  // a stream drawing the frame again: a probe frame's hitch grows with them); fewer take the
  // passes in rounds ahead of each selection (apply/probes.cpp, round_frames). 0: as many as the
  // governor finds room for.
  int probe_passes = 0;
  // GLBUDGET_TRANSITION_ORDER=0: the temporal filter blends the levels as the paper does,
  // instead of taking its one-level steps cheapest first (loop/governor.hpp, ordered_transition)
  bool transition_order = true;
  bool feedback = true;  // GLBUDGET_FEEDBACK=0: no correction from measured power (the paper's open loop)
  // GLBUDGET_FEEDBACK_OWN=1: a measured configuration's correction moves from the additive fit
  // towards its own windows' residual (loop/power_feedback.hpp, own_residuals)
  bool feedback_own = false;
  // GLBUDGET_EXPLORE_HELD=0: a run held over a power budget at a measured configuration, where
  // the range says the cheapest draws less, stays held rather than drawing the cheapest for one
  // window (loop/governor.hpp, explore_when_held)
  bool explore_held = true;
  // GLBUDGET_MEASURED_AT_WINDOWS=1: a configuration measured in the run is weighed, and taken for
  // an end of a share's range, at its windows' measured power moved by the model's change between
  // their counts and the frame's (loop/governor.hpp, measured_at_windows)
  bool measured_at_windows = false;
  // GLBUDGET_REMEMBER_FRAMES=N: a configuration whose frames have left the model's history enters
  // its fits as N frames of their mean; 0: forgotten; -1: not given, the model's default
  // (model/run_time_model.hpp, remembered_frames)
  int64_t remember_frames = -1;
  // GLBUDGET_BEST_BAND=S: under a share of the range, the top (the best configuration's power now)
  // stays within S of its windows' measured power above P_m, a measured cheapest within S of its
  // own (loop/governor.hpp, best_band); `off`: no bound
  double best_band = 0.1;
  // GLBUDGET_METER_WINDOWS=1: a window of the settled configuration read as a meter reads it,
  // probes included, over the budget selects again at once (loop/governor.hpp, meter_windows)
  bool meter_windows = true;
  // GLBUDGET_LEVEL_INTERACTIONS=calibrated|additive|model|scaled: where `glbudget calibrate --app`
  // measured each level alone, how a combination of levels is predicted (loop/governor.hpp,
  // level_interactions; model/additive_levels.hpp)
  loop::LevelInteractions level_interactions = loop::LevelInteractions::scaled;
  // GLBUDGET_ERROR_FEEDBACK=0: under an error budget, the estimates are not corrected by the
  // error probes measured of the configuration shown
  bool error_feedback = true;
  // GLBUDGET_PROBE_STRETCH=0: the governor never asks for rarer probes (loop/governor.hpp,
  // probe_stretch_gain)
  bool probe_stretch = true;
  // GLBUDGET_PROBE_MAX_AGE_S: settled probes come often enough that each pass in the scene is
  // probed again within this many seconds, however rare the settled period or the governor's
  // stretch would make them (apply/probes.cpp); 0: no bound. At 10 fps the settled period
  // alone left a pass's estimate 120-160 frames old at the selections, and their rank
  // correlation over the configurations moved with where the rare probes fell
  // (docs/evaluation/probes/probe-max-age.md).
  double probe_max_age_s = 10.0;
  // GLBUDGET_KEEP_SHARE: the share of 1-s windows within a power budget the governor's margins
  // aim at (loop/power_feedback.hpp and loop/probe_overhead.hpp, keep_share). A run of 60 s has
  // about 53 windows: aimed at 0.95, a run's own share fell under 0.95 in 3 of 12 runs (each
  // one window short), aimed at 0.98 in 1 of 12, at 0.007 more true error
  // (docs/evaluation/budgets.md, "the share of windows kept").
  double keep_share = 0.98;
  // GLBUDGET_FIRST_SAVING_DISCOUNT: the share of an unmeasured configuration's predicted saving
  // the governor does not count on until it has measured a configuration beyond the one the
  // app started in (loop/power_feedback.hpp, first_saving_discount); 0, the default: off.
  double first_saving_discount = 0.0;
  // GLBUDGET_SURPRISE_FLOOR: the least share of the power the governor takes a configuration
  // never measured to draw over its corrected prediction (loop/power_feedback.hpp,
  // surprise_floor_share); 0.02 by default; 0 or off: only what the run's first windows showed.
  double surprise_floor = 0.02;
  // GLBUDGET_WARM_BLITS=0: the blits a switch of scale makes are not made once ahead on tiny
  // images (apply/blit_warmup.cpp); the first switch to each scale then pays the driver's
  // shader builds for them.
  bool warm_blits = true;
  // GLBUDGET_TEST_HIDE_EXTENSIONS=GL_ARB_timer_query,...: a test switch (tests/interpose/
  // faults_test.cpp); the shim's capability probe (detect_caps) takes these extensions, and the
  // features they name even where the core version includes them, as absent.
  std::vector<std::string> hide_extensions;
  // GLBUDGET_TEST_OUT_OF_MEMORY=pass:level,...: a test switch (tests/interpose/shadowing_test.cpp);
  // while building that level's variant the shim asks the driver for a buffer no machine has,
  // so that the driver raises a real GL_OUT_OF_MEMORY.
  std::vector<std::pair<std::string, size_t>> test_out_of_memory;
  // GLBUDGET_TEST_MEASURE_DELAY_MS=N: a test switch (tests/interpose/third_party_apps_test.cpp);
  // the governor thread takes N ms longer to measure each probe frame, as on a CPU too slow for
  // the probes the app's frame rate brings.
  uint64_t test_measure_delay_ms = 0;
};

const Options& options();

// True when GLBUDGET_TEST_HIDE_EXTENSIONS names `extension` (exact name, "GL_ARB_timer_query").
bool extension_hidden(const char* extension);

// Exposed for tests of the parser: parses `env` (a NULL-terminated environ-style array),
// writing warnings to `warn`.
Options parse_options(char** env, std::string* warnings);

}  // namespace glbudget
