// Prints how long each step of the governor's decision loop (governor/loop) takes on the
// paper's space, 6 passes x 3 levels = 729 configurations: the synthetic app of
// tests/governor/synthetic_scene.hpp driven in closed loop through the Governor for a few
// thousand frames under a 40 % budget. Each step as the loop timed it (calls, mean, max),
// the selection's steps also timed alone (median of many calls) next to a naive baseline
// timed in the same run. Paper §5.5/§6.3: fit 2.6 ms, reuse 0.7 ms, predict all 0.02 ms,
// estimate errors and select 0.03 ms. Usage: governor_steps_bench [FRAMES] (default 6000).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numeric>
#include <string>
#include <vector>

#include "glbudget/loop/governor.hpp"
#include "glbudget/model/power_curve.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget;
using model::Configuration;

namespace {

volatile double g_sink = 0.0;  // keeps results alive

// Median over `rounds` of the mean time of `inner` calls, in microseconds.
template <typename F>
double median_us(F&& f, int inner, int rounds = 15) {
  std::vector<double> samples;
  for (int r = 0; r < rounds; ++r) {
    const auto start = std::chrono::steady_clock::now();
    for (int i = 0; i < inner; ++i) f();
    const std::chrono::duration<double, std::micro> elapsed = std::chrono::steady_clock::now() - start;
    samples.push_back(elapsed.count() / inner);
  }
  std::nth_element(samples.begin(), samples.begin() + rounds / 2, samples.end());
  return samples[rounds / 2];
}

loop::ErrorTable bench_errors(const model::ConfigurationSpace& space) {
  loop::ErrorTable table(space);
  for (std::size_t i = 0; i < space.pass_count(); ++i) {
    table.set(i, 1, 0.002 * static_cast<double>(i + 1));
    table.set(i, 2, 0.005 * static_cast<double>(i + 1));
  }
  return table;
}

// Baseline for predict-all: decode each configuration and evaluate the model from the counts,
// with the coefficients of every pass and level looked up by name.
void predict_all_naively(const model::testing::HiddenModel& hidden, const std::vector<model::PassFrame>& frame,
                         std::vector<double>& out) {
  const model::PlatformProfile profile = model::testing::synthetic_profile();
  out.resize(hidden.space.size());
  for (std::size_t index = 0; index < out.size(); ++index) {
    const Configuration c = hidden.space.decode(index);
    double alpha = 0.0;
    for (std::size_t i = 0; i < c.size(); ++i)
      alpha += model::pass_alpha(profile, hidden.coefficients(i, c[i]), frame[i].counts);
    out[index] = model::power_from_alpha(profile, alpha);
  }
}

// Baseline for the error estimates: decode each configuration and add up its passes' errors.
void estimate_all_naively(const loop::ErrorTable& errors, const model::ConfigurationSpace& space,
                          std::vector<double>& out) {
  out.resize(space.size());
  for (std::size_t index = 0; index < out.size(); ++index) out[index] = errors.estimate(space.decode(index));
}

// Baseline for selection: sort all configurations by error, take the first within budget.
std::size_t select_by_sorting(const std::vector<double>& power, const std::vector<double>& error, double budget) {
  std::vector<std::size_t> order(power.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return error[a] < error[b]; });
  for (std::size_t i : order) {
    if (power[i] <= budget) return i;
  }
  return order.front();
}

void row(const char* step, const loop::RunningStats& s, double alone_us, const char* baseline, double baseline_us,
         const char* paper) {
  std::printf("%-22s %6zu %9.2f %9.2f", step, s.count, s.mean_us, s.max_us);
  if (alone_us >= 0.0)
    std::printf(" %9.2f", alone_us);
  else
    std::printf(" %9s", "");
  if (baseline_us >= 0.0)
    std::printf("   %-28s %9.2f", baseline, baseline_us);
  else
    std::printf("   %-28s %9s", baseline, "");
  std::printf("   %s\n", paper);
}

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(300, std::atoi(argv[1])) : 6000;
  const model::testing::HiddenModel hidden = model::testing::six_pass_hidden_model();
  model::testing::SceneGenerator scene(hidden, 0.2, 7);
  loop::GovernorSettings settings;
  settings.power = *model::parse_budget("40%");
  loop::Governor governor(model::testing::synthetic_profile(), hidden.space, bench_errors(hidden.space), settings);

  // Closed loop at 60 fps along a slow camera path (tests/governor/loop_test.cpp's App).
  loop::RunningStats on_frame;
  Configuration drawn(6, 0);
  loop::FrameRecord record;
  for (int k = 0; k < frames; ++k) {
    const model::FrameSample sample = scene.sample(k / 64, drawn);
    record.frame = static_cast<std::uint64_t>(k);
    record.time_ns = static_cast<std::int64_t>(k) * 16'666'667;
    record.power_w = sample.power_w;
    record.configuration = drawn;
    record.passes = sample.passes;
    const auto start = std::chrono::steady_clock::now();
    const loop::Decision decision = governor.on_frame(record);
    on_frame.add(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count());
    drawn = decision.next;
  }
  const loop::StepTimes& t = governor.step_times();

  // The selection's steps alone, on the model and errors the loop ended with.
  std::vector<double> power, error, naive_power, naive_error;
  const model::RunTimeModel& model = governor.model();
  const double predict_us = median_us(
      [&] {
        model.predict_all(power);
        g_sink = power[7];
      },
      5000);
  predict_all_naively(hidden, record.passes, naive_power);
  const double naive_predict_us = median_us(
      [&] {
        predict_all_naively(hidden, record.passes, naive_power);
        g_sink = naive_power[7];
      },
      500);
  const double estimate_us = median_us(
      [&] {
        governor.errors().estimate_all(error);
        g_sink = error[7];
      },
      5000);
  const double naive_estimate_us = median_us(
      [&] {
        estimate_all_naively(governor.errors(), hidden.space, naive_error);
        g_sink = naive_error[7];
      },
      500);
  model::Selection selection;
  const double select_us =
      median_us([&] { selection = model::select_configuration(power, error, settings.power); }, 5000);
  const double sort_us =
      median_us([&] { g_sink = static_cast<double>(select_by_sorting(power, error, selection.budget_w)); }, 500);

  double worst_error_difference = 0.0, worst_power_difference = 0.0;
  for (std::size_t i = 0; i < error.size(); ++i) {
    worst_error_difference = std::max(worst_error_difference, std::abs(error[i] - naive_error[i]));
    worst_power_difference = std::max(worst_power_difference, std::abs(power[i] - naive_power[i]));
  }

  std::printf(
      "glbudget governor loop, 6 passes x 3 levels = %zu configurations, %d frames at 60 fps, budget 40%%, "
      "selection every %zu frames\n",
      hidden.space.size(), frames, settings.select_frames);
  std::printf("%-22s %6s %9s %9s %9s   %-28s %9s   %s\n", "step (us)", "calls", "mean", "max", "alone",
              "baseline (alone)", "baseline", "paper");
  row("on_frame, all steps", on_frame, -1.0, "", -1.0, "");
  row("  predict frame", t.predict_frame, -1.0, "", -1.0, "");
  row("  learn (every frame)", t.learn, -1.0, "", -1.0, "");
  row("    of which fits", t.fit, -1.0, "", -1.0, "fit 2600 + reuse 700");
  row("  predict all", t.predict_all, predict_us, "decode + evaluate each", naive_predict_us, "20");
  row("  estimate errors", t.estimate_errors, estimate_us, "decode + add up each", naive_estimate_us,
      "30 (with select)");
  row("  select", t.select, select_us, "sort by error, scan", sort_us, "30 (with estimate)");
  std::printf("fits %zu (history fits %zu), selections %zu, final target", model.fits(), model.history_fits(),
              governor.selections());
  for (int level : governor.target()) std::printf(" %d", level);
  std::printf("; predict-all vs. the hidden model: worst %.3f W; error table vs. naive: worst %.1e\n",
              worst_power_difference, worst_error_difference);
  std::printf("the shim's log line: %s\n", loop::describe(t).c_str());
  return 0;
}
