#include "glbudget/loop/probe_overhead.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "normal_quantile.hpp"

namespace glbudget::loop {
namespace {
constexpr double kRecentWeight = 1.0 / 8.0;
constexpr double kExcessWeight = 1.0 / 4.0;
constexpr double kShareDecay = 1.0 - 1.0 / 200.0;
constexpr double kIntervalWeight = 1.0 / 32.0;
constexpr double kLongestInterval_s = 0.5;
// A probe frame is its own length: drawn again in up to eight streams, it lasted 5-5.6 frames of
// the app's pace on the demo's Sponza at 10 frames a second (0.49-0.56 s, a sweep of six passes),
// and counted as a pause, no sweep there was ever measured and the windows were held to the
// probes of one pass before. It is a pause only past this many frames at the recent rate (a
// shader built on the spot, a breakpoint).
constexpr double kLongestProbeFrames = 16.0;
constexpr double kLongestProbeFrame_s = 2.0;  // and past 2 s whatever the pace (an app at 2-3 frames a second)
// Of the windows a budget may leave over it (1 - keep_share), the share left to the probes'
// windows: the other half is the sensor's scatter's, which the feedback's margin is for.
constexpr double kProbeShareOfOver = 0.5;
constexpr std::size_t kLeastForSpread = 8;  // probes measured before their spread is read
// Probes of a kind measured before other kinds are read from it. Fewer scatter too much: on
// the demo's Sponza the first probe of one pass measured 7 J and two of two passes 23-27 J; read
// as a ratio of 3.6, they made a sweep's margin 19 W.
constexpr std::size_t kLeastForKind = 4;
// A ratio measured between two kinds is kept within this factor of sweep_excess_factor's.
constexpr double kRatioBand = 2.0;
}  // namespace

double sweep_excess_factor(int sweep_streams) { return std::max(1.0, (sweep_streams + 2) / 4.0); }

namespace {
// What a probe of `to` streams draws against one of `from` by sweep_excess_factor's guess.
double guessed_ratio(int from, int to) { return sweep_excess_factor(to) / sweep_excess_factor(from); }
}  // namespace

void ProbeOverhead::Record::add(double excess, int streams) {
  recent[measured % recent.size()] = {excess, streams};
  ++measured;
  for (Kind& kind : kinds) {
    if (kind.streams == streams) {
      kind.level += kExcessWeight * (excess - kind.level);
      ++kind.measured;
      return;
    }
  }
  kinds.push_back({streams, excess, 1});
}

double ProbeOverhead::Record::level(int streams) const {
  if (kinds.empty()) return std::numeric_limits<double>::quiet_NaN();
  // The kind itself where measured; else between the kinds measured often enough on both
  // sides, or from the nearest such by sweep_excess_factor; before any is, from the kind
  // measured most.
  const Kind *below = nullptr, *above = nullptr, *most = nullptr;
  for (const Kind& kind : kinds) {
    if (kind.streams == streams) return kind.level;
    if (!most || kind.measured > most->measured) most = &kind;
    if (kind.measured < kLeastForKind) continue;
    if (kind.streams < streams && (!below || kind.streams > below->streams)) below = &kind;
    if (kind.streams > streams && (!above || kind.streams < above->streams)) above = &kind;
  }
  if (below && above) {
    const double t = static_cast<double>(streams - below->streams) / (above->streams - below->streams);
    return below->level + t * (above->level - below->level);
  }
  const Kind& from = below ? *below : above ? *above : *most;
  return from.level * guessed_ratio(from.streams, streams);
}

double ProbeOverhead::Record::ratio(int from, int to) const {
  const double guess = guessed_ratio(from, to);
  const double a = level(from), b = level(to);
  // Kinds whose probes draw no more than their neighbours carry no ratio: the guess's.
  if (!(a > 0.0) || !(b > 0.0)) return guess;
  return std::clamp(b / a, guess / kRatioBand, guess * kRatioBand);
}

double ProbeOverhead::Record::as_kind(const Sample& sample, int streams) const {
  return sample.streams == streams ? sample.excess : sample.excess * ratio(sample.streams, streams);
}

double ProbeOverhead::Record::largest(int streams) const {
  const std::size_t n = std::min<std::size_t>(measured, 4);
  double out = as_kind(recent[(measured - 1) % recent.size()], streams);
  for (std::size_t i = 1; i < n; ++i) out = std::max(out, as_kind(recent[(measured - 1 - i) % recent.size()], streams));
  return out;
}

double ProbeOverhead::Record::quantile(double z, int streams) const {
  const std::size_t n = std::min(measured, recent.size());
  if (n < kLeastForSpread) return std::numeric_limits<double>::quiet_NaN();
  std::array<double, 16> excess{};
  double mean = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    excess[i] = as_kind(recent[i], streams);
    mean += excess[i] / static_cast<double>(n);
  }
  double squares = 0.0;
  for (std::size_t i = 0; i < n; ++i) squares += (excess[i] - mean) * (excess[i] - mean);
  return mean + z * std::sqrt(squares / static_cast<double>(n - 1));
}

void ProbeOverhead::set_sweep_streams(int streams) { planned_streams_ = streams > 0 ? streams : kOnePassStreams; }

double ProbeOverhead::kind_factor(int streams) const {
  const int kind = streams > 0 ? streams : kOnePassStreams;
  const Record* record = source(false).first;
  return record ? record->ratio(planned_streams_, kind) : guessed_ratio(planned_streams_, kind);
}

void ProbeOverhead::close_span() {
  if (span_measured_) (span_at_best_ ? at_best_ : away_).add(span_excess_w_, span_streams_);
  span_left_ = 0;
  span_excess_w_ = 0.0;
  span_measured_ = false;
  span_paused_ = false;
  span_at_best_ = false;
  span_streams_ = kOnePassStreams;
}

std::pair<const ProbeOverhead::Record*, double> ProbeOverhead::source(bool shown_best) const {
  if (shown_best && at_best_.measured > 0) return {&at_best_, 0.0};
  if (away_.measured > 0) return {&away_, 0.0};
  if (at_best_.measured > 0) return {&at_best_, best_stream_w_};
  return {nullptr, 0.0};
}

double ProbeOverhead::excess_w(bool shown_best) const {
  const auto [record, stream_w] = source(shown_best);
  return record ? record->level(planned_streams_) + stream_w : 0.0;
}

void ProbeOverhead::add(bool probe, double power_w, std::int64_t time_ns, bool shown_best, int sweep_streams) {
  // The frame's length in frames at the recent rate: its power counts for as long as it lasted
  // (1 where either is not known).
  double length_frames = 1.0;
  bool paused = false;
  if (time_ns >= 0 && last_time_ns_ >= 0 && time_ns > last_time_ns_) {
    const double interval = static_cast<double>(time_ns - last_time_ns_) * 1e-9;
    // Where no frame rate is known (every interval a pause: an app under 2 frames a second),
    // frames count one each.
    if (interval_s_ > 0.0) {
      length_frames = interval / interval_s_;
      paused = interval >= kLongestInterval_s &&
               !(probe && length_frames < kLongestProbeFrames && interval < kLongestProbeFrame_s);
    }
    // A pause (loading, a breakpoint) is no frame rate: it would hold the windows' frames low
    // for seconds after it.
    if (interval < kLongestInterval_s)
      interval_s_ = interval_s_ > 0.0 ? interval_s_ + kIntervalWeight * (interval - interval_s_) : interval;
  }
  if (time_ns >= 0) last_time_ns_ = time_ns;
  // Decaying counts rather than a running mean, so that the share is right from the first
  // frames and follows a probe period changed mid-run.
  probes_ = probes_ * kShareDecay + (probe ? 1.0 : 0.0);
  frames_ = frames_ * kShareDecay + 1.0;
  if (since_probe_ >= 0.0) since_probe_ += 1.0;
  if (probe) {
    if (since_probe_ > 0.0)
      gap_frames_ = gap_frames_ > 0.0 ? gap_frames_ + kExcessWeight * (since_probe_ - gap_frames_) : since_probe_;
    since_probe_ = 0.0;
  }
  if (probe) {
    close_span();
    span_left_ = kProbeSpanFrames;
    span_at_best_ = shown_best;
    // A probe shown at the best draws no stream of it: counted as its kind, the streams it
    // would draw elsewhere.
    span_streams_ = sweep_streams > 0 ? sweep_streams + (shown_best ? 1 : 0) : kOnePassStreams;
  }
  const bool finite = std::isfinite(power_w);
  last_in_span_ = span_left_ > 0;
  if (span_left_ > 0) {
    // A pause in the span (a breakpoint, loading, a shader built on the spot) is not the
    // probe's: its power over seconds would stand for dozens of frames. The span is not counted.
    if (paused) {
      span_paused_ = true;
      span_measured_ = false;
    }
    // The probe frame's power must be measured for the span to count; the next frame's
    // excess is added when it is.
    if (finite && have_recent_ && !span_paused_ && (probe || span_measured_)) {
      span_excess_w_ += length_frames * (power_w - recent_w_);
      span_measured_ = true;
    }
    if (--span_left_ == 0) close_span();
    return;
  }
  if (!finite) return;
  recent_w_ = have_recent_ ? recent_w_ + kRecentWeight * (power_w - recent_w_) : power_w;
  have_recent_ = true;
}

double ProbeOverhead::watts(bool shown_best) const {
  return probes_measured() == 0 ? 0.0 : std::max(0.0, excess_w(shown_best)) * share();
}

double ProbeOverhead::share() const {
  // One in the period the shim plans, or once probes have come twice in their mean gap, or in
  // the frames since the last where that is longer (they slowed down or stopped).
  if (period_in_force_ > 0.0 && probes_measured() > 0) return 1.0 / std::max(period_in_force_, since_probe_);
  if (gap_frames_ > 0.0) return 1.0 / std::max(gap_frames_, since_probe_);
  return frames_ > 0.0 ? probes_ / frames_ : 0.0;
}

double ProbeOverhead::probes_per_window(double frames) const {
  // A probe's span of three frames touches two more window starts than the window has frames.
  return share() * (frames + kProbeSpanFrames - 1);
}

double ProbeOverhead::frames_per_window(double window_s) const {
  return interval_s_ > 0.0 && window_s > 0.0 ? std::max(1.0, window_s / interval_s_) : 0.0;
}

double ProbeOverhead::largest_recent_excess_w(bool shown_best) const {
  const auto [record, stream_w] = source(shown_best);
  return record ? std::max(0.0, record->largest(planned_streams_) + stream_w) : 0.0;
}

double ProbeOverhead::whole_excess_margin_w(double window_s, bool shown_best) const {
  const double frames = frames_per_window(window_s);
  if (probes_measured() == 0 || frames <= 0.0) return 0.0;
  double excess = largest_recent_excess_w(shown_best);
  const auto [record, stream_w] = source(shown_best);
  if (record && keep_share_ < 1.0) {
    // Of the windows holding a probe, the share that may be over the budget.
    const double per_window = std::min(1.0, probes_per_window(frames));
    const double over = per_window > 0.0 ? kProbeShareOfOver * (1.0 - std::max(0.0, keep_share_)) / per_window : 1.0;
    if (over < 0.5) {
      const double q = record->quantile(normal_quantile(1.0 - over), planned_streams_);
      if (std::isfinite(q)) excess = std::max(excess, q + stream_w);
    }
  }
  return excess / frames;
}

double ProbeOverhead::rare_gap(double window_s, double keep_share) const {
  const double frames = frames_per_window(window_s);
  if (frames <= 0.0 || !(keep_share < 1.0)) return 0.0;
  // One frame more than the bound: window_margin_w must find it at or under.
  return std::ceil((frames + kProbeSpanFrames - 1) / (kProbeShareOfOver * (1.0 - std::max(0.0, keep_share)))) + 1.0;
}

double ProbeOverhead::watts_at_gap(double gap, bool shown_best) const {
  return probes_measured() == 0 || !(gap > 0.0) ? 0.0 : std::max(0.0, excess_w(shown_best)) / gap;
}

double ProbeOverhead::window_margin_w(double window_s, double keep_share, bool shown_best) const {
  const double frames = frames_per_window(window_s);
  if (probes_measured() == 0 || frames <= 0.0) return watts(shown_best);
  // Under one probe per window, that share of windows holds one (and the rest none).
  if (probes_per_window(frames) <= kProbeShareOfOver * (1.0 - keep_share)) return watts(shown_best);
  return std::max(watts(shown_best), whole_excess_margin_w(window_s, shown_best));
}

}  // namespace glbudget::loop
