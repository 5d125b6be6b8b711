#include <catch2/catch.hpp>

#include "glbudget/analysis/cost_fit.hpp"
#include "glbudget/analysis/resolved_frame.hpp"
#include "glbudget/model/platform_costs.hpp"
#include "glbudget/analysis/replay.hpp"

using namespace glbudget::model;
using namespace glbudget::analysis;

namespace {
const std::string kLogs = GLBUDGET_SOURCE_DIR "/tests/data/logs/";

// A committed log with its variant table and platform profile, all required to load.
struct Recording {
  PlatformProfile profile;
  VariantTable variants;
  FrameLog log;
};
Recording load_recording(const std::string& name, const std::string& profile_name) {
  const auto profile = load_platform_profile(kLogs + profile_name + ".profile.json");
  auto variants = load_variant_table(kLogs + name + ".variants.json");
  auto log = read_frame_log_file(kLogs + name + ".csv");
  REQUIRE(profile);
  REQUIRE(variants);
  REQUIRE(log);
  return {*profile, std::move(*variants), std::move(*log)};
}
}  // namespace

TEST_CASE("replay of the synthetic six-pass log: fitted and reused within 2% MAPE, better than the baseline",
          "[model][replay]") {
  const Recording r = load_recording("synthetic_six_pass", "synthetic_six_pass");
  const auto* profile = &r.profile;
  const auto* variants = &r.variants;
  const auto* log = &r.log;
  CHECK(variants->space.size() == 729);

  const ReplayReport report = replay_frames(frames_of_busiest_context(*log), *profile, *variants);
  CHECK(report.frames == 300);
  CHECK(report.frames_unusable == 0);
  CHECK(report.fits >= 1);
  // Every frame after the first fitting window is predicted, in one class or the other.
  CHECK(report.ours_fitted.per_frame.count() + report.ours_reused.per_frame.count() == 270);
  CHECK(report.ours_reused.per_frame.count() > 0);
  CHECK(report.ours_fitted.per_frame.mape_percent() < 2.0);
  CHECK(report.ours_reused.per_frame.mape_percent() < 2.0);
  CHECK(report.baseline_fitted.per_frame.count() == report.ours_fitted.per_frame.count());
  CHECK(report.baseline_reused.per_frame.mape_percent() > report.ours_reused.per_frame.mape_percent());
  CHECK(report.configuration_runs == 5);
  CHECK(report.ours_switch.count() == 4);  // one prediction of the next run per change
  CHECK(report.scored.size() == 270);
  // Averages over 30 frames of one run: fewer pairs, never more error than a frame's worst.
  CHECK(report.ours_reused.averaged.count() > 0);
  CHECK(report.ours_reused.averaged.max_share_of_range() <= report.ours_reused.per_frame.max_share_of_range());
  // chi and psi are only loosely identified here (instructions and texels per fragment both
  // fall with every level in this log), but both costs are positive.
  CHECK(report.reuse.chi > 0.0);
  CHECK(report.reuse.psi > 0.0);
}

TEST_CASE("replay without a variant table treats every program as its own pass", "[model][replay]") {
  const auto profile = load_platform_profile(kLogs + "synthetic_six_pass.profile.json");
  const auto log = read_frame_log_file(kLogs + "synthetic_six_pass.csv");
  REQUIRE(profile);
  REQUIRE(log);
  const ReplayReport report = replay_frames(log->frames, *profile, VariantTable{});
  CHECK(report.ours_reused.per_frame.count() == 0);  // no configurations known
  CHECK(report.ours_fitted.per_frame.count() > 0);
  // A set of programs not seen before has no coefficients: the check fails and it is refitted.
  CHECK(report.checks_failed >= 1);
  CHECK(report.fits >= 2);
}

// Logs recorded from the demo renderer under the shim with the cpu sensor, paced at 2 fps, in
// eight configurations that move all six knobs along one camera path
// (tests/data/logs/record_demo_logs.py). Real data: the goal is the paper's (<= 2 % MAPE), not
// reached with this sensor (its frame-to-frame scatter alone is 1.8-3.7 %); what is asserted
// is what these recordings show with a margin, so that a regression in the model, the reader
// or the replay fails here. The figures are printed by `glbudget replay` and
// bench/model/replay_summary.py.
TEST_CASE("replay of the demo renderer's recorded logs: every scene predicted, better than the baseline",
          "[model][replay]") {
  for (const char* scene : {"hall", "sponza", "valley", "subway"}) {
    INFO(scene);
    const Recording r = load_recording(std::string("demo_") + scene, "demo_cpu");
    const auto* profile = &r.profile;
    const auto* variants = &r.variants;
    const auto* log = &r.log;
    // Valley has neither metals nor reflections: those knobs drop out of its space.
    CHECK(variants->space.size() == (std::string(scene) == "valley" ? 81u : 729u));
    const ReplayReport report = replay_frames(frames_of_busiest_context(*log), *profile, *variants);
    CHECK(report.frames == 320);
    CHECK(report.frames_unusable <= 16);  // each run's first and last swap carry no power or counts
    CHECK(report.configuration_runs == 8);
    CHECK(report.fits >= 8);          // one per configuration run
    CHECK(report.history_fits >= 6);  // all but the first run's fit span several
    CHECK(report.ours_reused.per_frame.count() >= 150);
    CHECK(report.ours_switch.count() == 7);
    // Recorded: fitted 2.3-7.6 %, reused 4.8-6.1 % per frame, switches 4.2-6.1 %; the
    // baseline 7.4-18.3 % on the same reused frames.
    CHECK(report.ours_fitted.per_frame.mape_percent() < 10.0);
    CHECK(report.ours_reused.per_frame.mape_percent() < 9.0);
    CHECK(report.ours_switch.mape_percent() < 13.0);
    CHECK(report.ours_reused.per_frame.mape_percent() < report.baseline_reused.per_frame.mape_percent());
    // The paper's measure (all frames, 30-frame averages): recorded 3.7-5.5 % against
    // the baseline's 7.2-17.1 %.
    CHECK(report.ours_all.averaged.mape_percent() < 7.0);
    CHECK(report.ours_all.averaged.mape_percent() < report.baseline_all.averaged.mape_percent());
    // Predicting a switch beats assuming the power stays as it was (recorded 4-6 % against 8-19 %).
    CHECK(report.unchanged_switch.count() == 7);
    CHECK(report.switches.size() == 7);
    CHECK(report.ours_switch.mape_percent() < report.unchanged_switch.mape_percent());
    // The floor is the sensor's scatter around each run's mean: below every model's error.
    CHECK(report.floor.per_frame.mape_percent() < report.ours_reused.per_frame.mape_percent());
    CHECK(report.floor.averaged.mape_percent() < 1.0);
  }
}

// The same eight configurations recorded on an NVIDIA H100 with the nvml sensor (energy
// counter), 1920x1080, paced at 44 fps, 176 frames each in one process stepping through them
// (bench/gpu/real_gpu.py, 2026-11-27; docs/real-gpu.md), the variant tables measured through
// the same manifest. Real power: the goal (<= 2 %) is not met there; what is asserted is what
// the recording shows, with a margin: every frame fitted within 15 % (recorded 5.3-12.1 %), and
// the paper's measure below the baseline on every scene (recorded 6.4-11.0 % against
// 18.1-54.8 %).
TEST_CASE("replay of the demo recorded on an H100 with real power", "[model][replay]") {
  for (const char* scene : {"hall", "sponza", "valley", "subway"}) {
    INFO(scene);
    const Recording r = load_recording(std::string("h100/demo_") + scene, "h100/demo_nvml");
    CHECK(r.variants.space.size() == (std::string(scene) == "valley" ? 81u : 729u));
    const ReplayReport report = replay_frames(frames_of_busiest_context(r.log), r.profile, r.variants);
    CHECK(report.frames == 1408);
    CHECK(report.frames_unusable <= 4);  // the first swap, and a frame the energy counter did not move in
    CHECK(report.configuration_runs == 8);
    CHECK(report.ours_fitted.per_frame.mape_percent() < 15.0);
    CHECK(report.ours_all.averaged.mape_percent() < report.baseline_all.averaged.mape_percent());
    CHECK(report.ours_all.averaged.mape_percent() < 14.0);
  }
}

TEST_CASE("replay without the fit over several configurations follows the paper's path", "[model][replay]") {
  const Recording r = load_recording("demo_subway", "demo_cpu");
  const auto* profile = &r.profile;
  const auto* variants = &r.variants;
  const auto* log = &r.log;
  ReplayOptions paper;
  paper.history.enabled = false;
  const auto frames = frames_of_busiest_context(*log);
  const ReplayReport one_window = replay_frames(frames, *profile, *variants, {}, paper);
  const ReplayReport several = replay_frames(frames, *profile, *variants);
  CHECK(one_window.history_fits == 0);
  CHECK(one_window.fits == several.fits);
  // Recorded on Subway: 17.4 % against 6.0 % on reused frames.
  CHECK(several.ours_reused.per_frame.mape_percent() < 0.6 * one_window.ours_reused.per_frame.mape_percent());
}

namespace {
// The frames of a recording in the configurations they were drawn in.
std::vector<ConfiguredSample> configured_samples(const Recording& r) {
  PassNames names(r.variants.space);
  return glbudget::analysis::configured_samples(frames_of_busiest_context(r.log), r.variants, names);
}
}  // namespace

TEST_CASE("replay of each demo scene with the costs calibrated on the other three", "[model][replay][costs]") {
  const char* scenes[] = {"hall", "sponza", "valley", "subway"};
  std::vector<Recording> recordings;
  std::vector<std::vector<ConfiguredSample>> samples;
  for (const char* scene : scenes) {
    recordings.push_back(load_recording(std::string("demo_") + scene, "demo_cpu"));
    samples.push_back(configured_samples(recordings.back()));
  }
  double with_sum = 0.0, without_sum = 0.0;
  for (std::size_t held_out = 0; held_out < 4; ++held_out) {
    INFO(scenes[held_out]);
    std::vector<CostLog> others;
    for (std::size_t s = 0; s < 4; ++s) {
      if (s != held_out) others.push_back({samples[s], &recordings[s].variants.space});
    }
    const auto fit = fit_platform_costs(others, recordings[held_out].profile);
    REQUIRE(fit);
    CHECK(fit->samples_used > 900);
    PlatformProfile calibrated = recordings[held_out].profile;
    calibrated.costs = fit->costs;
    const auto frames = frames_of_busiest_context(recordings[held_out].log);
    const ReplayReport with = replay_frames(frames, calibrated, recordings[held_out].variants);
    const ReplayReport without = replay_frames(frames, recordings[held_out].profile, recordings[held_out].variants);
    // Recorded: all frames over 30-frame averages 1.5-5.4 % with the costs, 3.7-5.5 %
    // without; switches 2.8-6.2 %, against 8.3-19.5 % for "no change".
    CHECK(with.ours_all.averaged.mape_percent() < 6.0);
    CHECK(with.ours_switch.mape_percent() < 7.0);
    CHECK(with.ours_switch.mape_percent() < with.unchanged_switch.mape_percent());
    CHECK(with.ours_all.averaged.mape_percent() < with.baseline_all.averaged.mape_percent());
    with_sum += with.ours_all.averaged.mape_percent();
    without_sum += without.ours_all.averaged.mape_percent();
  }
  // Recorded: 2.9 % against 4.8 % on average over the four scenes.
  CHECK(with_sum / 4.0 < without_sum / 4.0 - 1.0);
}
