#pragma once
// Beyond the paper: a quality-probe frame draws the frame a second time, so its power is
// not any configuration's and the model never learns from it; but the user's meter sees it,
// in every window a probe falls into. ProbeOverhead measures what probes add to the mean
// power of all frames, probe frames included: each probe's excess over the frames drawn just
// before it, summed over the probe frame and the two after it (the probe's image is compared
// one frame late, behind a fence, and some of that work spills into the frame after), times
// the share of frames that are probes.
// The excess is energy, as a meter reads it: each frame's excess times its length in frames at
// the recent rate. A probe frame that overruns its slot at the app's pace (1.5-2.5 slots at 10
// frames a second on the demo's Hall and Sponza) counts for every slot it fills, and the frame
// after it, shortened while the pacing catches up, for the part of one it fills. Counted as a
// frame each, the demo's probes at 50 % looked half what they cost on Sponza and Subway, and
// a tenth less on Hall (docs/evaluation/budgets.md, run L).
// A selection keeps the excess under the budget besides the spread's margin, and windows are
// held to the budget with it.
// The mean is what a long meter reading sees; a window of a second sees all of a probe or
// none of it. Where more windows hold a probe than the probes' part of the share a budget may
// leave over it (a probe every 60 frames at 10 frames a second: one window in six), each such
// window must fit its probe's whole excess, and the selection keeps that instead
// (window_margin_w).
// Probed rarely enough that at most that share of windows holds one (rare_gap), each window
// keeps the mean again: the governor asks for that where it buys quality (governor.hpp).
// A probe shown at the best configuration draws one stream fewer: the best, s0, is what the
// app drew. Its excess is no guide to a probe anywhere else, which a selection under a budget
// is about: on the demo at 10 frames a second, probes shown at the best drew 0-1 J over their
// neighbours and those shown elsewhere 1.5-3.3 J (runs L, M and N), so the first selection,
// made while the app still drew its best, kept almost nothing for them, and its first windows
// holding a probe went over the budget. Such probes are kept apart: until a probe shown
// elsewhere is measured, their excess plus the stream they lack (one frame of the best
// configuration above idle power, set_best_stream_w) stands in for it.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace glbudget::loop {

// The frames whose power a probe raises: its own, the one that reads its comparison back, and
// one more (on llvmpipe under the cpu estimate the third still drew 0.3-2.6 W over its
// neighbours on the demo's Hall).
inline constexpr int kProbeSpanFrames = 3;

// The shortest gap between probes, in frames, that leaves at most one probe's span in any
// window of `frames_per_window` frames (0: not known). A window's margin covers one probe's
// whole excess (ProbeOverhead::window_margin_w); probes closer than this put two into some
// windows.
inline std::uint64_t one_probe_per_window_gap(double frames_per_window) {
  if (!(frames_per_window > 0.0) || !(frames_per_window < 1e9)) return 0;
  return static_cast<std::uint64_t>(std::ceil(frames_per_window)) + kProbeSpanFrames - 1;
}

// A probe frame's excess measuring every pass at once in `sweep_streams` streams (the best and
// one a pass) against a probe of one pass shown elsewhere (two streams: the best and the pass's
// cheapest), where each stream costs as much and the probe frame's own work (its read-backs and
// comparisons, the shadow targets) as much as two: (streams + 2) / 4, at least 1. Measured on
// the demo at 10 frames a second: Valley's sweeps (five streams) drew 3.0-4.1 J over their
// neighbours against 1.5-2.8 J for its probes of one pass (about 1.7 times; 1.75 here), Hall's and
// Sponza's (seven) 1.5-2.2 times theirs (2.25 here).
double sweep_excess_factor(int sweep_streams);
constexpr int kOnePassStreams = 2;

class ProbeOverhead {
 public:
  // Every frame, in order; power NaN when not measured; time_ns (when the frame ended, any
  // origin) gives the frame rate, negative when not known; shown_best: the frame drew the
  // best configuration; sweep_streams: the streams of a probe frame that measured every pass
  // at once (0: a probe of one pass) (both read on probe frames).
  void add(bool probe, double power_w, std::int64_t time_ns = -1, bool shown_best = false, int sweep_streams = 0);
  // What a probe shown elsewhere draws beyond one shown at the best, until one is measured:
  // the best configuration's stream, about one frame of its power above idle (watts times
  // frames; less where the stream follows the app's frame up to its first lowered pass, more
  // where a best frame lasts longer than the frames drawn now). A value that is not finite
  // leaves the last one; one under 0 is 0.
  void set_best_stream_w(double w) {
    if (std::isfinite(w)) best_stream_w_ = w > 0.0 ? w : 0.0;
  }
  // The frames between probes the shim plans now (0: not known; the gaps measured then
  // tell). Probes may come rarer than planned, never more often.
  void set_period_in_force(double frames) { period_in_force_ = frames > 0.0 ? frames : 0.0; }
  // The streams the shim's probes draw from now on where each measures several passes at once
  // (GLBUDGET_PROBE_SWEEP: the best and one a pass), 0 where they probe one pass (two streams):
  // what is read of the probes (watts(), whole_excess_margin_w()) is for probes of that kind.
  // Every probe measured counts for every kind, converted by what each kind is measured to
  // cost (kind_factor): the governor moves between sweeps of more or fewer passes and probes
  // of one from one selection to the next, and a record of one kind alone, started again at
  // each move, held a window to the largest of one or two probes, and to sweep_excess_factor's
  // guess until the kind was measured (the demo's Valley at 60 %: a sweep of three passes
  // planned at 1.5 times the probes of one pass drew 1.7 times theirs and put its window over).
  void set_sweep_streams(int streams);
  int planned_streams() const { return planned_streams_; }
  // What a probe of `streams` streams (two: one pass) costs against one of the kind planned,
  // shown elsewhere: the ratio of the two kinds' excess, each as measured, or, for a kind not
  // measured, between the kinds measured four times or more on either side of it, else from the
  // nearest such (before any is, the kind measured most) by sweep_excess_factor's ratio; kept
  // within twice and half that guess. The guess before any probe is measured.
  double kind_factor(int streams) const;
  // The frame last added is a probe's or one of the two after it: its power is not its
  // configuration's own.
  bool in_span() const { return last_in_span_; }

  // What probes cost is read for probes shown away from the best (the default: what a
  // selection under a budget moves to) or, with shown_best, at the best: the probes measured
  // there, else those measured elsewhere.
  // Watts the probes add to the mean of all frames (>= 0; 0 before a probe with power).
  double watts(bool shown_best = false) const;
  // The mean excess of a probe (its span's frames, each times its length in frames at the
  // recent rate: watts times frames) over the frames before it (may be negative), and the
  // share of recent frames that were probes.
  double excess_w(bool shown_best = false) const;
  double share() const;
  // What a selection keeps under the budget for the probes so that about `keep_share` of the
  // windows of window_s seconds, probes included, stay within it: watts() where at most half
  // of 1 - keep_share of the windows hold a probe (the other half is left to the sensor's
  // scatter), or the frame rate is not known; else a probe's whole excess spread over one
  // window's frames.
  double window_margin_w(double window_s, double keep_share, bool shown_best = false) const;
  // Frames in a window of window_s seconds at the recent frame rate (0: not known).
  double frames_per_window(double window_s) const;
  // Probes in a window of that many frames at the recent share (under one: the share of
  // windows holding one).
  double probes_per_window(double frames) const;
  // A probe's whole excess spread over one window's frames (0 while unknown): the largest of
  // the last four probes', since each window must fit the probe it holds, not the mean probe
  // (their excess scatters by a tenth or more with the configuration shown and the frame). With
  // a keep share set (set_keep_share), at least the quantile of the last 16 probes' excess
  // (their mean and spread, once 8 are measured) that leaves over the budget no more than the
  // probes' half of 1 - keep_share of all windows, where windows hold probes at the recent
  // share: where most windows hold one, the largest of four covers about four in five of them
  // (the demo's Hall and Subway at 40-50 %, a probe every 16 frames: 3-4 windows over in a
  // run, each holding a probe whose excess was over that largest, by 0.3-0.9 W).
  double whole_excess_margin_w(double window_s, bool shown_best = false) const;
  double largest_recent_excess_w(bool shown_best = false) const;
  // The share of windows to keep within the budget (FeedbackSettings::keep_share) for
  // whole_excess_margin_w's quantile; 1 (the default): the largest of the last four alone.
  void set_keep_share(double keep_share) { keep_share_ = keep_share; }
  // The frames between probes from which at most 1 - keep_share of the windows hold one, so
  // that window_margin_w is the mean (0: the frame rate is not known).
  double rare_gap(double window_s, double keep_share) const;
  // What the probes would add to the mean with one every `gap` frames.
  double watts_at_gap(double gap, bool shown_best = false) const;
  std::size_t probes_measured() const { return away_.measured + at_best_.measured; }
  // Of them, those shown at a configuration other than the best.
  std::size_t probes_measured_away() const { return away_.measured; }

 private:
  // The probes measured, shown at the best or elsewhere, of every kind.
  struct Sample {
    double excess = 0.0;
    int streams = kOnePassStreams;
  };
  struct Kind {
    int streams = kOnePassStreams;
    double level = 0.0;  // its excess, exponentially (about 4 probes)
    std::size_t measured = 0;
  };
  struct Record {
    std::array<Sample, 16> recent = {};  // the last probes' excess, by measured modulo 16
    std::size_t measured = 0;
    std::vector<Kind> kinds;
    void add(double excess, int streams);
    // A kind's excess: measured, or from the kinds measured (kind_factor); NaN before any.
    double level(int streams) const;
    // What a probe of `to` streams draws against one of `from` (kind_factor).
    double ratio(int from, int to) const;
    // A probe's excess as a probe of `streams` streams would have drawn it.
    double as_kind(const Sample& sample, int streams) const;
    double largest(int streams) const;  // of the last four (may be negative; requires measured > 0)
    // Mean + z * spread of the recent ones; NaN under eight.
    double quantile(double z, int streams) const;
  };
  void close_span();
  // The record a read of what probes cost takes (watts()): at the best its own where measured,
  // else those shown elsewhere, else those at the best with the stream they lack, which is
  // returned beside it (0 otherwise); nullptr before any probe is measured.
  std::pair<const Record*, double> source(bool shown_best) const;

  double recent_w_ = 0.0;  // the frames before, exponentially (about 8 frames)
  bool have_recent_ = false;
  // The probe being measured: frames of its span still to come, and its excess so far.
  int span_left_ = 0;
  double span_excess_w_ = 0.0;
  bool span_measured_ = false;
  bool span_paused_ = false;            // a frame of the span lasted kLongestInterval_s or more
  bool span_at_best_ = false;           // the probe was shown at the best configuration
  int span_streams_ = kOnePassStreams;  // the probe's kind: its streams shown elsewhere
  bool last_in_span_ = false;
  Record away_, at_best_;
  double best_stream_w_ = 0.0;
  double keep_share_ = 1.0;
  int planned_streams_ = kOnePassStreams;  // the kind of probe the shim plans now
  double probes_ = 0.0, frames_ = 0.0;     // decaying counts (about 200 frames), until a gap is seen
  // Frames between probes, exponentially (about 4 gaps), and since the last probe: sparse
  // probes (one every 600 frames) are not a share the decaying counts can hold.
  double gap_frames_ = 0.0;
  double since_probe_ = -1.0;  // -1: no probe yet
  double period_in_force_ = 0.0;
  std::int64_t last_time_ns_ = -1;
  double interval_s_ = 0.0;  // between frames, exponentially (about 32 frames); 0: not known
};

}  // namespace glbudget::loop
