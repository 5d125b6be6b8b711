#include "governing.hpp"
#include "messages.hpp"

#include <pthread.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <unordered_map>
#include <vector>

#include "frame_log.hpp"
#include "glbudget/loop/from_manifest.hpp"
#include "glbudget/loop/governor.hpp"
#include "glbudget/model/platform_profile.hpp"
#include "glbudget/model/selection.hpp"
#include "glbudget/model/variant_table.hpp"
#include "glbudget/sensors/profile_path.hpp"
#include "glbudget/sensors/sensor.hpp"
#include "options.hpp"
#include "probes.hpp"
#include "signals_blocked.hpp"
#include "glbudget/quality/luma_image.hpp"
#include "glbudget/quality/ssim.hpp"

namespace glbudget {

namespace {

// Programs outside the manifest's passes (every program, without a manifest) are modelled as
// one more pass of a single level; the built-in render scale scales it with the rest.
constexpr const char* kAppPass = "app";

manifest::Manifest governed_manifest(const manifest::Manifest& m) {
  manifest::Manifest out = m;
  manifest::Pass app;
  app.name = kAppPass;
  app.levels.emplace_back();
  out.passes.push_back(app);
  for (manifest::Pass& p : out.passes) {
    bool scales_window = false;
    for (const manifest::Level& l : p.levels)
      for (const manifest::Target& t : l.targets)
        scales_window |=
            t.kind == manifest::Target::Kind::default_framebuffer || t.kind == manifest::Target::Kind::window_sized;
    if (scales_window) {
      // The window holds every pass's final image: its scale shrinks whatever draws into it.
      p.scales.clear();
      for (const manifest::Pass& q : out.passes)
        if (!q.match.empty() || q.name == kAppPass) p.scales.push_back(q.name);
    }
  }
  return out;
}

// The levels' instruction and texel costs `glbudget calibrate --app` measured for this app:
// GLBUDGET_COSTS, else the default path by executable name if that file exists. Without them
// the model predicts savings only from levels that change how much is drawn (scales, skipped
// passes), not from levels that change what each fragment costs.
struct MeasuredSpace {
  model::ConfigurationSpace space;
  std::optional<model::PlatformCosts> costs;                    // this app's, when calibrate --app measured its power
  std::optional<model::VariantTable::MeasuredRange> range;      // and its best and cheapest configurations'
  std::vector<std::pair<model::Configuration, double>> powers;  // every configuration it measured
  std::map<std::pair<std::string, int>, double> error_ratios;   // k by pass name and level, where it probed them
};
MeasuredSpace measured_space(const manifest::Manifest& m, bool budget) {
  const std::string& named = options().costs_path;
  if (named == "off") return {loop::space_from_manifest(m), std::nullopt, std::nullopt, {}, {}};
  std::string path = named.empty() ? sensors::default_variant_table_path(executable_name()) : named;
  std::error_code ec;
  if (named.empty() && (path.empty() || !std::filesystem::is_regular_file(path, ec))) {
    const bool has_programs = std::any_of(m.passes.begin(), m.passes.end(), [](const manifest::Pass& p) {
      return std::any_of(p.levels.begin(), p.levels.end(),
                         [](const manifest::Level& l) { return l.changes_program(); });
    });
    if (budget && has_programs)
      say("no measured costs of the manifest's shader levels (" +
          (path.empty() ? std::string("no cache directory") : path) +
          "): the model predicts savings from render scales and skipped passes only; "
          "`glbudget calibrate --app -- APP` measures them");
    return {loop::space_from_manifest(m), std::nullopt, std::nullopt, {}, {}};
  }
  const std::optional<model::VariantTable> table = model::load_variant_table(path);  // says why when it fails
  if (!table) return {loop::space_from_manifest(m), std::nullopt, std::nullopt, {}, {}};
  std::vector<std::string> problems;
  model::ConfigurationSpace space = loop::space_from_manifest(m, *table, problems);
  for (const std::string& p : problems) say(path + ": " + p);
  // The table measured the manifest's passes; the governor's space may add passes of one
  // level (the "app" pass), which leave its best and cheapest configurations the table's.
  bool same_ends = space.pass_count() >= table->space.pass_count();
  for (std::size_t i = 0; same_ends && i < space.pass_count(); ++i)
    same_ends = i < table->space.pass_count()
                    ? space.passes()[i].levels.size() == table->space.passes()[i].levels.size()
                    : space.passes()[i].levels.size() == 1;
  if (!same_ends) return {std::move(space), table->platform_costs, std::nullopt, {}, table->error_ratios};
  return {std::move(space), table->platform_costs, table->measured_range, table->measured_power_w, table->error_ratios};
}

std::string default_profile_path() {
  if (const char* p = std::getenv("GLBUDGET_PROFILE"); p && *p) return p;
  const char* sensor = std::getenv("GLBUDGET_SENSOR");
  return sensors::default_profile_path(sensor ? sensor : "");
}

struct Frame {
  std::vector<FrameRow> rows;
};

// A frame of one context: frame numbers restart in each.
using FrameKey = std::pair<int, uint64_t>;

std::atomic<uint64_t> g_drift{0};  // probe_drift_count()

size_t image_bytes(const ProbeCapture& capture) {
  size_t bytes = 0;
  for (const std::vector<uint8_t>& image : capture.images) bytes += image.size();
  return bytes;
}

class GovernorThread {
 public:
  GovernorThread(loop::Governor governor, manifest::Manifest manifest,
                 const std::map<std::pair<std::string, int>, double>& error_ratios)
      : governor_(std::move(governor)), manifest_(std::move(manifest)) {
    for (size_t i = 0; i < manifest_.passes.size(); ++i)
      for (int l = 1; l < static_cast<int>(manifest_.passes[i].levels.size()); ++l)
        if (const auto k = error_ratios.find({manifest_.passes[i].name, l}); k != error_ratios.end())
          measured_ratios_[{static_cast<int>(i), l}] = k->second;
    probed_.assign(manifest_.passes.size(), false);
  }

  void start() {
    const SignalsBlocked blocked;  // the governor takes none of the app's signals
    pthread_create(&thread_, nullptr, &GovernorThread::main, this);
  }

  // Render threads never wait on the governor thread: what finds its queues locked waits in
  // `waiting_` (guarded by waiting_mu_, which only render threads and stop() take) until the
  // next hand-over of either kind, or until stop() delivers it.
  void push(Frame&& frame) {
    std::lock_guard lock(waiting_mu_);
    waiting_frames_.push_back(std::move(frame));
    hand_over_waiting();
  }
  void push_probe(ProbeCapture&& capture) {
    unmeasured_.fetch_add(1, std::memory_order_relaxed);
    unmeasured_bytes_.fetch_add(image_bytes(capture), std::memory_order_relaxed);
    std::lock_guard lock(waiting_mu_);
    waiting_probes_.push_back(std::move(capture));
    hand_over_waiting();
  }

  bool backlogged() const {
    return unmeasured_.load(std::memory_order_relaxed) >= kProbeBacklog ||
           unmeasured_bytes_.load(std::memory_order_relaxed) >= kProbeBacklogBytes;
  }

  bool levels(Levels* out) const {
    const uint64_t packed = decision_.load(std::memory_order_acquire);
    if (!(packed >> 63)) return false;
    out->count = static_cast<int>((packed >> 56) & 0x1f);
    for (int i = 0; i < out->count && i < 14; ++i) out->level[i] = static_cast<int8_t>((packed >> (4 * i)) & 0xf);
    return true;
  }

  void stop() {
    {
      std::lock_guard waiting(waiting_mu_);
      std::lock_guard lock(mu_);
      move_waiting();
      stopping_ = true;
    }
    wake_.notify_one();
    pthread_join(thread_, nullptr);
  }

  // From a signal handler that ends the process: every frame handed over is decided and its
  // rows (held ones too) go to the log, within `limit`. Waits by polling, never by a lock.
  // Probes still waiting are measured for the first half of it only: up to kProbeBacklog of
  // them can take longer than the limit where the SSIM is slow (a loaded CPU), and their
  // errors would steer no later frame, while the rows behind them are what the log must keep
  // (those of a probe left unmeasured go out without its probe_error).
  void drain_from_signal(std::chrono::nanoseconds limit) {
    measure_until_ns_.store(sensors::monotonic_now_ns() + limit.count() / 2, std::memory_order_release);
    drained_.store(false, std::memory_order_release);
    drain_asked_.store(true, std::memory_order_release);
    const timespec step{0, 1'000'000};
    for (auto waited = std::chrono::nanoseconds(0); waited < limit; waited += std::chrono::milliseconds(1)) {
      if (drained_.load(std::memory_order_acquire)) return;
      nanosleep(&step, nullptr);
    }
  }

  void note_program(PassId program, int pass) {
    std::lock_guard lock(names_mu_);
    pass_of_program_[program] = pass;
  }

 private:
  static void* main(void* self) {
    static_cast<GovernorThread*>(self)->run();
    return nullptr;
  }

  // Holding waiting_mu_.
  void hand_over_waiting() {
    std::unique_lock lock(mu_, std::try_to_lock);
    if (!lock.owns_lock()) return;
    move_waiting();
    lock.unlock();
    wake_.notify_one();
  }

  // Holding waiting_mu_ and mu_.
  void move_waiting() {
    for (Frame& f : waiting_frames_) queue_.push_back(std::move(f));
    for (ProbeCapture& p : waiting_probes_) probes_.push_back(std::move(p));
    waiting_frames_.clear();
    waiting_probes_.clear();
  }

  void run() {
    std::deque<Frame> work;
    std::deque<ProbeCapture> probes;
    for (;;) {
      {
        std::unique_lock lock(mu_);
        // A signal handler cannot notify a condition variable: a drain it asks for is looked
        // for at every kDrainPoll.
        wake_.wait_for(lock, kDrainPoll, [&] {
          return stopping_ || !queue_.empty() || !probes_.empty() || drain_asked_.load(std::memory_order_acquire);
        });
        if (drain_asked_.load(std::memory_order_acquire) && waiting_mu_.try_lock()) {
          move_waiting();
          waiting_mu_.unlock();
        }
        work.swap(queue_);
        probes.swap(probes_);
        if (work.empty() && probes.empty()) {
          if (stopping_) {
            measure_pending(nullptr, true);
            flush_held(nullptr, true);
            return;
          }
          if (drain_asked_.exchange(false, std::memory_order_acq_rel)) {
            measure_pending(nullptr, true);
            flush_held(nullptr, true);
            drained_.store(true, std::memory_order_release);
          }
          continue;
        }
      }
      for (ProbeCapture& p : probes) pending_.push_back({decided_, std::move(p)});
      probes.clear();
      for (Frame& f : work) {
        if (!f.rows.empty()) {
          const FrameKey key{f.rows.front().context, f.rows.front().frame};
          measure_pending(&key, false);
        }
        decide(f);
      }
      work.clear();
      measure_pending(nullptr, false);
    }
  }

  // A probe is measured just before its own frame is decided (or the first later frame of its
  // context), not as soon as it is handed over: its capture usually comes before the frame's
  // counters, and were it measured at once, how many frames it was learnt ahead of, and how
  // many probes were learnt together, would hang on the threads' timing. In frame order, a
  // run's decisions and its log's est_error follow the probes the same way at any speed.
  // `before`: the frame about to be decided; null measures those waiting for kHoldFrames
  // decided frames (their context may draw no more, or its frame numbers restarted), and with
  // `all`, every one.
  void measure_pending(const FrameKey* before, bool all) {
    for (auto it = pending_.begin(); it != pending_.end();) {
      const ProbeCapture& p = it->capture;
      const bool due = all || (before ? before->first == p.context && before->second >= p.frame
                                      : decided_ - it->handed_at >= kHoldFrames);
      if (!due) {
        ++it;
        continue;
      }
      if (sensors::monotonic_now_ns() < measure_until_ns_.load(std::memory_order_acquire)) measure(p);
      unmeasured_bytes_.fetch_sub(image_bytes(p), std::memory_order_relaxed);
      unmeasured_.fetch_sub(1, std::memory_order_relaxed);
      it = pending_.erase(it);
    }
  }

  // A probe frame's errors (paper §6.2): the shown frame against s0, and each s_i^lmax
  // against s0. e_i(lmax) is measured; the levels between take k times it (level_ratio).
  // A pass's latest probe replaces its earlier ones: the same frame drawn twice has no noise to
  // average away, and in a moving scene an older frame's error is the one further from the
  // frames to come (averaging with it lowered the rank correlation on subway and valley).
  // Every stream's error is logged (probe_streams).
  void measure(const ProbeCapture& p) {
    if (const uint64_t delay_ms = options().test_measure_delay_ms)
      std::this_thread::sleep_for(std::chrono::milliseconds(delay_ms));
    if (p.width <= 0 || p.height <= 0) return;
    // Compared on the GPU in the app's context, or here from the images read back.
    const bool compared = !p.errors.empty();
    std::vector<quality::LumaImage> luma;
    if (!compared) {
      if (p.images.size() != p.streams.size() + 1) return;
      for (const std::vector<uint8_t>& image : p.images) {
        if (image.size() != static_cast<size_t>(p.width) * p.height * 4) return;
        luma.push_back(quality::luma_from_8bit(image.data(), p.width, p.height, 4));
      }
    }
    quality::SsimOptions options;
    options.scale = probe_ssim_scale(p.width, p.height);
    options.threads = 1;  // beside the app's render threads
    auto error = [&](size_t a, size_t b) -> std::optional<double> {
      if (!compared) return 1.0 - quality::ssim(luma[a].view(), luma[b].view(), options);
      for (const ProbeCapture::Compared& k : p.errors)
        if ((k.a == a && k.b == b) || (k.a == b && k.b == a)) return k.error;
      return std::nullopt;
    };
    ProbeResult& result = results_[{p.context, p.frame}];
    const size_t best = best_image(p);
    if (best == 0)
      result.shown_error = 0.0;
    else if (const std::optional<double> e = error(0, best))
      result.shown_error = *e;
    for (size_t s = 0; s < p.streams.size(); ++s) {
      if (s + 1 == best) continue;
      const int pass = only_pass_changed(p.streams[s]);
      if (pass < 0) continue;
      const std::optional<double> measured = error(best, s + 1);
      if (!measured) continue;
      std::string& streams = result.streams;
      char text[32];
      std::snprintf(text, sizeof text, "=%.6f", *measured);
      streams += (streams.empty() ? "" : ";") + format_levels(p.streams[s]) + text;
      // Other levels (GLBUDGET_PROBE_LEVELS=all) are logged only.
      take_cheapest_level_error(pass, p.streams[s].level[pass], *measured);
    }
    // A frame shown with one pass at its cheapest level and the others at their best is that
    // pass's probe itself (the probe draws no stream for it): its error against the best is
    // that level's. Without this a pass kept at its cheapest (an app whose one knob is the
    // window's resolution) kept the error its probe measured before, however the scene went on.
    if (best != 0 && result.shown_error)
      if (const int pass = only_pass_changed(p.shown); pass >= 0)
        take_cheapest_level_error(pass, p.shown.level[pass], *result.shown_error, false);
    // A pass whose programs drew in neither this probe frame nor the one before is not in the
    // scene: no level of it changes the image, so its error is 0 rather than the stand-in
    // (which would rank configurations that differ only there apart) until it is probed again.
    for (size_t i = 0; i < manifest_.passes.size(); ++i) {
      const manifest::Pass& pass = manifest_.passes[i];
      if (pass.levels.size() < 2 || pass_in_scene(pass, i, p.passes_drawn)) continue;
      for (int l = 1; l < static_cast<int>(pass.levels.size()); ++l) governor_.errors().set(i, l, 0.0);
      set_probe_pass_error(i, 0.0);
    }
    // After the table took this probe's errors: the estimate of what was shown as the next
    // selection will make it. (The best configuration shown is ignored there: its error is 0.)
    if (result.shown_error) {
      model::Configuration shown(manifest_.passes.size(), 0);
      for (size_t i = 0; i < shown.size(); ++i) shown[i] = p.shown[static_cast<int>(i)];
      governor_.shown_error(shown, *result.shown_error);
    }
    flush_held(nullptr, false);
  }

  // The one pass whose level is not its best in `levels` (within the manifest); -1 if none
  // or several.
  int only_pass_changed(const Levels& levels) const {
    const int count = std::clamp(levels.count, 0, kMaxPasses);
    const int pass = model::only_pass_changed(model::Configuration(levels.level, levels.level + count));
    return pass >= 0 && static_cast<size_t>(pass) < manifest_.passes.size() ? pass : -1;
  }

  // A pass's error measured at `level`: at its cheapest level, the pass's error in the table
  // (and the levels between by their ratio), and, from a probe's stream (`drift`), a drift if it
  // moved from the last probe's. The shown image's error counts no drift: it is measured at
  // every probe frame, not in turn, and would call bursts of probes (each costing about five
  // frames' power) where the streams' own turns would not.
  void take_cheapest_level_error(int pass, int level, double e, bool drift = true) {
    const int lmax = static_cast<int>(manifest_.passes[static_cast<size_t>(pass)].levels.size()) - 1;
    if (level != lmax) return;
    loop::ErrorTable& table = governor_.errors();
    if (drift && probed_[static_cast<size_t>(pass)] && moved(table.error(static_cast<size_t>(pass), lmax), e))
      g_drift.fetch_add(1, std::memory_order_relaxed);
    probed_[static_cast<size_t>(pass)] = true;
    table.set(static_cast<size_t>(pass), lmax, e);
    set_probe_pass_error(static_cast<size_t>(pass), e);
    for (int l = 1; l < lmax; ++l) table.set(static_cast<size_t>(pass), l, level_ratio(pass, l) * e);
  }

  // Whether a pass's fresh error is far enough from its last probe's to say the scene changed
  // beneath the estimates: a quarter of the larger, and more than SSIM's noise between frames
  // of a still scene.
  static bool moved(double before, double now) {
    return std::abs(now - before) > std::max(kDriftAbsolute, kDriftRelative * std::max(before, now));
  }

  // k = e_i(l) / e_i(lmax) (paper §6.2): the ratio `glbudget calibrate --app` measured for the
  // level, else the manifest's `error` values' ratio where both levels have one, else l / lmax.
  double level_ratio(int pass, int l) const {
    const auto measured = measured_ratios_.find({pass, l});
    if (measured != measured_ratios_.end()) return measured->second;
    const manifest::Pass& mp = manifest_.passes[static_cast<size_t>(pass)];
    const int lmax = static_cast<int>(mp.levels.size()) - 1;
    const std::optional<double> own = mp.levels[static_cast<size_t>(l)].error, top = mp.levels.back().error;
    return own && top && *top > 0.0 ? std::clamp(*own / *top, 0.0, 1.0) : static_cast<double>(l) / lmax;
  }

  // Rows of probe frames wait for their measured errors: until the probe's result arrives, or
  // until `now` (the frame being decided; null when a probe was measured) is kHoldFrames past
  // them in their own context, or kHoldFrames * 4 frames of any context have been decided since
  // (their context may draw no more; a probe frame's capture can be dropped). `stopping`: the
  // process ends; every row goes out. Frame numbers restart in each context, so rows and
  // results are matched by context and frame. A result usually comes before its rows: the
  // governor thread measures a probe just before it decides the probe's frame (measure_pending).
  void flush_held(const FrameKey* now, bool stopping) {
    for (auto it = held_.begin(); it != held_.end();) {
      const auto found = results_.find({it->context, it->frame});
      const bool known = found != results_.end();
      const bool waited = stopping || decided_ - it->decided_at > kHoldFrames * 4 ||
                          (now && now->first == it->context && now->second >= it->frame + kHoldFrames);
      if (!known && !waited) {
        ++it;
        continue;
      }
      for (FrameRow& row : it->rows) {
        if (known) {
          if (found->second.shown_error) row.probe_error = *found->second.shown_error;
          row.probe_streams = found->second.streams;
        }
        FrameLog::get().push(row);
      }
      if (known) results_.erase(found);
      it = held_.erase(it);
    }
    // A result whose rows went out without it (it was measured too late): rows come in frame
    // order within a context, so once a later frame of its context is decided they have.
    std::erase_if(results_, [&](const auto& r) {
      const auto last = last_decided_.find(r.first.first);
      return last != last_decided_.end() && last->second >= r.first.second;
    });
  }

  // The program's pass as the model knows it: its manifest pass's index in the space, else the
  // "app" pass, the space's last.
  model::PassIndex pass_index(PassId program) {
    std::lock_guard lock(names_mu_);
    auto it = pass_of_program_.find(program);
    return static_cast<model::PassIndex>(it == pass_of_program_.end() ? manifest_.passes.size() - 1 : it->second);
  }

  void decide(Frame& f) {
    if (f.rows.empty()) return;
    const FrameRow& first = f.rows.front();
    loop::FrameRecord record;
    record.frame = first.frame;
    record.time_ns = first.time_ns;
    record.power_w = first.energy.valid ? first.energy.mean_power_w : std::nan("");
    record.probe = first.probe;
    record.probe_period = static_cast<double>(probe_period_in_force());
    record.sweeping_streams = probe_sweep_streams();
    record.probe_sweep_streams = first.probe_sweep_streams;
    record.sweepable_streams = probe_sweepable_streams();
    // The shim's levels ("0:2:1"), then the "app" pass's only level.
    for (size_t at = 0; at < first.configuration.size();) {
      size_t end = first.configuration.find(':', at);
      if (end == std::string::npos) end = first.configuration.size();
      record.configuration.push_back(std::atoi(first.configuration.substr(at, end - at).c_str()));
      at = end + 1;
    }
    record.configuration.resize(manifest_.passes.size(), 0);
    for (const FrameRow& row : f.rows) {
      const model::PassIndex index = pass_index(row.pass);
      model::PassFrame* pass = nullptr;
      for (model::PassFrame& p : record.passes)
        if (p.pass == index) pass = &p;
      if (!pass) {
        record.passes.push_back({index, {0.0, 0.0, 0.0}});
        pass = &record.passes.back();
      }
      pass->counts.batches += static_cast<double>(row.batches);
      pass->counts.vertices += row.vertices < 0 ? std::nan("") : static_cast<double>(row.vertices);
      pass->counts.fragments += row.fragments < 0 ? std::nan("") : static_cast<double>(row.fragments);
    }
    const loop::Decision d = governor_.on_frame(record);
    set_probe_period_wanted(governor_.probe_period_wanted(), governor_.probe_bursts_spaced(),
                            governor_.probe_streams_fit());
    set_probe_selection_due(governor_.next_selection_frame(), governor_.settings().select_frames,
                            governor_.transitioning());
    // Observing only for the probes, the governor has nothing to tell.
    if (governor_.governing())
      for (; notes_said_ < governor_.notes().size(); ++notes_said_) say(governor_.notes()[notes_said_]);
    if (d.event == loop::Event::select) write_selection();
    publish(d.next);
    // Observing for the probes alone, the model runs on no profile of the machine's: its
    // predictions are not watts, and there is no budget.
    const bool steering = governor_.governing();
    for (FrameRow& row : f.rows) {
      row.predicted_w = steering ? d.predicted_w : std::nan("");
      row.budget_w = steering ? d.budget_w : std::nan("");
      row.est_error = d.est_error;
      row.decision = loop::event_name(d.event);
    }
    // `first` lives in f.rows, which a probe frame's rows leave for held_ (and flush_held may
    // free at once).
    ++decided_;
    const FrameKey now{first.context, first.frame};
    last_decided_[now.first] = now.second;
    if (first.probe)
      held_.push_back({now.first, now.second, decided_, std::move(f.rows)});
    else
      for (FrameRow& row : f.rows) FrameLog::get().push(row);
    flush_held(&now, false);
  }

  // Every configuration's corrected prediction and estimated error at a selection, beside the
  // log (`glbudget report` draws them): LOG.selections.csv.
  void write_selection() {
    const std::string& log = options().log_path;
    if (log.empty() || selections_failed_) return;
    if (!selections_) {
      selections_ = std::fopen((log + ".selections.csv").c_str(), "w");
      if (!selections_) {
        selections_failed_ = true;
        say("cannot write " + log + ".selections.csv; the selections are not kept");
        return;
      }
      std::fputs(
          "frame,configuration,predicted_w,est_error,selected,budget_w,margin_w,weighed_w,range_low_w,range_high_w,"
          "probe_margin_w\n",
          selections_);
    }
    const loop::Governor::SelectionTable t = governor_.last_selection();
    const model::ConfigurationSpace& space = governor_.space();
    const bool weighed = t.weighed_w->size() == t.power_w->size();
    // Empty where not a share of the range, as the frame log leaves what was not measured.
    const auto watts = [](double w) {
      char text[32] = "";
      if (std::isfinite(w)) std::snprintf(text, sizeof text, "%.4f", w);
      return std::string(text);
    };
    const std::string range_low = watts(t.range_low_w), range_high = watts(t.range_high_w);
    for (size_t i = 0; i < t.power_w->size() && i < t.error->size(); ++i) {
      const model::Configuration c = space.decode(i);
      std::string text;
      for (size_t p = 0; p + 1 < c.size(); ++p) text += (p ? ":" : "") + std::to_string(c[p]);
      std::fprintf(selections_, "%llu,%s,%.4f,%.6f,%d,%.4f,%.4f,%.4f,%s,%s,%.4f\n",
                   static_cast<unsigned long long>(t.frame), text.c_str(), (*t.power_w)[i], (*t.error)[i],
                   i == t.chosen ? 1 : 0, t.budget_w, t.margin_w, weighed ? (*t.weighed_w)[i] : (*t.power_w)[i],
                   range_low.c_str(), range_high.c_str(), t.probe_margin_w);
    }
    std::fflush(selections_);
  }

  void publish(const model::Configuration& next) {
    // Without the trailing "app" pass; 4 bits a level, the count, and a valid bit.
    const size_t count = std::min<size_t>(next.size() - 1, 14);
    uint64_t packed = (uint64_t{1} << 63) | (static_cast<uint64_t>(count) << 56);
    for (size_t i = 0; i < count; ++i) packed |= static_cast<uint64_t>(next[i] & 0xf) << (4 * i);
    decision_.store(packed, std::memory_order_release);
  }

  loop::Governor governor_;
  manifest::Manifest manifest_;
  pthread_t thread_{};
  std::mutex mu_;
  std::condition_variable wake_;
  std::deque<Frame> queue_;
  bool stopping_ = false;
  std::atomic<uint64_t> decision_{0};
  std::mutex names_mu_;
  std::unordered_map<PassId, int> pass_of_program_;
  size_t notes_said_ = 0;
  std::deque<ProbeCapture> probes_;
  std::atomic<size_t> unmeasured_{0}, unmeasured_bytes_{0};  // probes pushed, not yet measured
  std::atomic<bool> drain_asked_{false}, drained_{false};    // drain_from_signal()
  // Probes are measured until then (monotonic ns): drain_from_signal() sets it.
  std::atomic<int64_t> measure_until_ns_{std::numeric_limits<int64_t>::max()};
  static constexpr std::chrono::milliseconds kDrainPoll{20};
  std::mutex waiting_mu_;
  std::vector<Frame> waiting_frames_;
  std::vector<ProbeCapture> waiting_probes_;
  struct Held {
    int context = 0;
    uint64_t frame = 0;
    uint64_t decided_at = 0;  // decided_ when held
    std::vector<FrameRow> rows;
  };
  struct PendingProbe {
    uint64_t handed_at = 0;  // decided_ when handed over
    ProbeCapture capture;
  };
  std::deque<PendingProbe> pending_;  // handed over, measured before their frames are decided
  struct ProbeResult {
    std::optional<double> shown_error;  // FrameRow::probe_error
    std::string streams;                // FrameRow::probe_streams
  };
  static constexpr uint64_t kHoldFrames = 8;
  static constexpr double kDriftAbsolute = 0.003, kDriftRelative = 0.25;
  std::vector<bool> probed_;  // by pass: its cheapest level has been probed
  uint64_t decided_ = 0;      // frames decided, of every context
  std::vector<Held> held_;
  std::map<FrameKey, ProbeResult> results_;                // by context and probe frame
  std::map<int, uint64_t> last_decided_;                   // frame, by context
  std::map<std::pair<int, int>, double> measured_ratios_;  // k by pass and level: calibrate --app's
  std::FILE* selections_ = nullptr;
  bool selections_failed_ = false;
};

GovernorThread* g_thread = nullptr;    // never destroyed: hooks may run during exit
std::atomic<bool> g_governing{false};  // frames pass through the thread
std::atomic<bool> g_steering{false};   // and it chooses their configuration (a budget is set)
thread_local Frame t_building;

}  // namespace

bool governor_start() {
  static std::once_flag once;
  std::call_once(once, [] {
    const Options& o = options();
    // Quality probes asked for without a budget: the thread measures them and logs, and
    // changes nothing (the Governor observes).
    const bool probes_asked = o.probe_period > 0;
    if (o.power.empty() && o.error.empty() && !probes_asked) return;
    loop::GovernorSettings settings;
    if (!o.power.empty()) {
      std::optional<model::Budget> b = model::parse_budget(o.power);  // says why when it fails
      if (b) settings.power = *b;
    }
    if (!o.error.empty()) {
      settings.error_budget = model::parse_error_budget(o.error);
      if (!settings.error_budget) say("GLBUDGET_ERROR='" + o.error + "' is not an error (1 - SSIM) in [0, 1]; ignored");
    }
    const bool budget = settings.power.kind != model::Budget::Kind::Off || settings.error_budget;
    if (!budget && !probes_asked) return;
    settings.select_frames = o.select_frames;
    settings.transition_s = o.transition_s;
    settings.ordered_transition = o.transition_order;
    settings.feedback.enabled = o.feedback;
    settings.feedback.own_residuals = o.feedback_own;
    settings.explore_when_held = o.explore_held;
    settings.measured_at_windows = o.measured_at_windows;
    if (o.remember_frames >= 0) settings.history.remembered_frames = static_cast<size_t>(o.remember_frames);
    settings.best_band = o.best_band;
    settings.paced_fps = o.fps;
    settings.meter_windows = o.meter_windows;
    settings.level_interactions = o.level_interactions;
    settings.error_feedback.enabled = o.error_feedback;
    settings.feedback.keep_share = o.keep_share;
    settings.feedback.first_saving_discount = o.first_saving_discount;
    settings.feedback.surprise_floor_share = o.surprise_floor;
    if (!o.probe_stretch) settings.probe_stretch_gain = 0.0;
    const std::string path = default_profile_path();
    std::optional<model::PlatformProfile> profile;
    // Observing for the probes alone needs no profile of its own (the model is not used).
    if (!path.empty() && (budget || std::getenv("GLBUDGET_PROFILE"))) profile = model::load_platform_profile(path);
    if (!profile && budget) {
      say("no platform profile (" + (path.empty() ? std::string("GLBUDGET_PROFILE is unset") : path) +
          "): the budget is not kept, the app runs unchanged; `glbudget calibrate` writes one");
      if (!probes_asked) return;
      settings.power = {};
      settings.error_budget.reset();
    }
    if (!profile) profile = model::PlatformProfile{};
    manifest::Manifest m = governed_manifest(active_manifest());
    MeasuredSpace measured = measured_space(m, budget);
    if (measured.costs) profile->costs = measured.costs;
    settings.calibrated_range = measured.range;
    settings.calibrated_powers = std::move(measured.powers);
    loop::Governor governor(*profile, std::move(measured.space), loop::errors_from_manifest(m), settings);
    const bool steering = governor.governing();
    g_thread = new GovernorThread(std::move(governor), std::move(m), measured.error_ratios);
    g_thread->start();
    g_governing = true;
    // A child forked without exec has no governor thread: it neither hands frames to it nor
    // waits for it (at exit, or for a drain on a fatal signal: Ctrl-C reaches the whole group).
    pthread_atfork(nullptr, nullptr, [] { g_governing = false; });
    g_steering = steering;
  });
  return g_governing;
}

bool governing() { return g_governing.load(std::memory_order_relaxed); }
bool governor_steering() { return g_steering.load(std::memory_order_relaxed); }

void governor_push(const FrameRow& row) {
  if (!t_building.rows.empty()) {
    const FrameRow& last = t_building.rows.back();
    if (last.frame != row.frame || last.context != row.context) governor_rows_done();
  }
  t_building.rows.push_back(row);
}

void governor_rows_done() {
  if (t_building.rows.empty() || !g_thread) return;
  g_thread->push(std::move(t_building));
  t_building = Frame{};
}

bool governor_levels(Levels* out) { return g_thread && g_steering && g_thread->levels(out); }

void governor_probe(ProbeCapture&& capture) {
  if (g_thread) g_thread->push_probe(std::move(capture));
}

void governor_stop() {
  if (!g_thread || !g_governing.exchange(false)) return;
  governor_rows_done();
  g_thread->stop();
}

bool governor_probes_backlogged() { return g_thread && g_thread->backlogged(); }

void governor_drain_from_signal() {
  if (g_thread && g_governing.load(std::memory_order_relaxed)) g_thread->drain_from_signal(std::chrono::seconds(2));
}

uint64_t probe_drift_count() { return g_drift.load(std::memory_order_relaxed); }

void note_program_pass(PassId program, int pass) {
  if (g_thread) g_thread->note_program(program, pass);
}

}  // namespace glbudget
