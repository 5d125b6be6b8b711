#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>

#include "glbudget/model/window_fit.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget::model;
using namespace glbudget::model::testing;

namespace {

// Passes of six_pass_hidden_model() by index, and of the small windows built here.
constexpr PassIndex kShading = 1, kShadows = 3, kA = 0, kB = 1;

const Configuration kMiddle{1, 1, 1, 1, 1, 1};

std::vector<FrameSample> window_of(SceneGenerator& scene, int first_frame, int frames,
                                   const Configuration& configuration) {
  std::vector<FrameSample> window;
  for (int t = first_frame; t < first_frame + frames; ++t) window.push_back(scene.sample(t, configuration));
  return window;
}

// Mean |predicted - true| over later frames, as a share of P_M - P_m.
double held_out_error(const PowerModel& model, SceneGenerator& scene, const Configuration& configuration) {
  double sum = 0.0;
  for (int t = 500; t < 600; ++t) {
    const auto counts = scene.counts(t);
    sum += std::abs(model.predict_power(counts) - scene.true_power(counts, configuration));
  }
  return sum / 100.0 / synthetic_profile().range_w();
}

void check_same_coefficients(const PowerModel& a, const PowerModel& b, double relative) {
  REQUIRE(a.fitted_passes() == b.fitted_passes());
  for (const auto& [pass, k] : fitted_of(a)) {
    const PassCoefficients* other = b.find(pass);
    REQUIRE(other != nullptr);
    CHECK(k.k_b == Approx(other->k_b).epsilon(relative).margin(1e-12));
    CHECK(k.k_v == Approx(other->k_v).epsilon(relative).margin(1e-12));
    CHECK(k.k_f == Approx(other->k_f).epsilon(relative).margin(1e-12));
  }
}

}  // namespace

TEST_CASE("fit recovers a hidden noiseless model exactly", "[model][fit]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  const auto window = window_of(scene, 0, 30, kMiddle);
  const WindowFitResult fit = fit_window(window, PowerModel(synthetic_profile()));
  CHECK(fit.samples_used == 30);
  CHECK(fit.columns == 18);
  CHECK(fit.held_terms == 0);
  check_same_coefficients(fit.model, scene.hidden().fitted_model_for(kMiddle), 2e-3);
}

TEST_CASE("fit under measurement noise predicts unseen frames of the configuration", "[model][fit]") {
  // Noise of 0.5% of the range on samples whose counts barely vary within the window
  // (18 unknowns, 30 samples): the held-out frames lie far along the camera path.
  SceneGenerator scene(six_pass_hidden_model(), /*noise_w=*/0.2);
  const WindowFitResult fit = fit_window(window_of(scene, 0, 30, kMiddle), PowerModel(synthetic_profile()));
  CHECK(held_out_error(fit.model, scene, kMiddle) < 0.02);
  for (const auto& [pass, k] : fitted_of(fit.model)) {
    CHECK(k.k_b >= 0.0);
    CHECK(k.k_v >= 0.0);
    CHECK(k.k_f >= 0.0);
  }
}

TEST_CASE("a pass that drew nothing keeps its coefficients and has no column", "[model][fit]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  PowerModel previous(synthetic_profile());
  const PassCoefficients kept{0.7, 0.8, 0.9};
  previous.set(kShadows, kept);
  auto window = window_of(scene, 0, 30, kMiddle);
  for (FrameSample& sample : window) {
    // The pass is listed but drew nothing; power is what the other five cost.
    std::erase_if(sample.passes, [](const PassFrame& p) { return p.pass == kShadows; });
    sample.power_w = scene.true_power(sample.passes, kMiddle);
    sample.passes.push_back({kShadows, {}});
  }
  const WindowFitResult fit = fit_window(window, previous);
  CHECK(fit.columns == 15);
  const PassCoefficients* shadows = fit.model.find(kShadows);
  REQUIRE(shadows != nullptr);
  CHECK(shadows->k_b == kept.k_b);
  CHECK(shadows->k_v == kept.k_v);
  CHECK(shadows->k_f == kept.k_f);
  CHECK(fit.model.find(kShading)->k_f == Approx(scene.hidden().coefficients(1, 1).k_f).epsilon(2e-3));
}

TEST_CASE("a window of identical frames holds what it cannot identify", "[model][fit][extremes]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  const PowerModel truth = scene.hidden().fitted_model_for(kMiddle);
  const FrameSample frame = scene.sample(3, kMiddle);
  const std::vector<FrameSample> window(30, frame);

  SECTION("starting from the truth, nothing moves") {
    const WindowFitResult fit = fit_window(window, truth);
    CHECK(fit.held_terms >= 17);  // one direction of 18 is identified
    check_same_coefficients(fit.model, truth, 1e-4);
  }
  SECTION("starting from a wrong model, only the identified combination moves") {
    PowerModel wrong(synthetic_profile());
    for (const auto& [pass, k] : fitted_of(truth)) wrong.set(pass, {k.k_b * 1.5, k.k_v * 1.5, k.k_f * 1.5});
    const WindowFitResult fit = fit_window(window, wrong);
    CHECK(fit.model.predict_power(frame.passes) == Approx(frame.power_w).epsilon(1e-4));
    for (const auto& [pass, k] : fitted_of(fit.model)) {
      CHECK(std::isfinite(k.k_b));
      CHECK(k.k_f > 0.0);
      CHECK(k.k_f < 1.5 * truth.find(pass)->k_f);  // no blow-up along unidentified directions
    }
  }
}

TEST_CASE("collinear passes are fitted as a sum, not as garbage", "[model][fit][extremes]") {
  // Two passes whose counts are always equal: only the sum of their coefficients is known.
  PowerModel truth(synthetic_profile());
  truth.set(kA, {0.5, 0.4, 3.0});
  truth.set(kB, {0.5, 0.4, 1.0});
  std::vector<FrameSample> window;
  for (int t = 0; t < 30; ++t) {
    const PassCounts c{100.0 + 10 * t, 5e5 + 3e4 * (t % 7), 1e7 + 4e6 * std::sin(t)};
    FrameSample sample{0.0, {{kA, c}, {kB, c}}};
    sample.power_w = truth.predict_power(sample.passes);
    window.push_back(sample);
  }
  const WindowFitResult fit = fit_window(window, PowerModel(synthetic_profile()));
  CHECK(fit.held_terms >= 3);
  const PassCoefficients a = *fit.model.find(kA);
  const PassCoefficients b = *fit.model.find(kB);
  CHECK(a.k_f + b.k_f == Approx(4.0).epsilon(1e-3));
  CHECK(a.k_f == Approx(b.k_f).epsilon(1e-6));  // split evenly from a zero start
  CHECK(fit.model.predict_power(window[4].passes) == Approx(window[4].power_w).epsilon(1e-5));
}

TEST_CASE("fewer samples than unknowns still improves the model without garbage", "[model][fit][extremes]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  const PowerModel truth = scene.hidden().fitted_model_for(kMiddle);
  PowerModel off(synthetic_profile());
  for (const auto& [pass, k] : fitted_of(truth)) off.set(pass, {k.k_b * 1.2, k.k_v * 1.2, k.k_f * 1.2});
  const auto window = window_of(scene, 0, 5, kMiddle);  // 5 samples, 18 unknowns
  const WindowFitResult fit = fit_window(window, off);
  CHECK(fit.held_terms > 0);
  double error_before = 0.0, error_after = 0.0;
  for (const FrameSample& sample : window) {
    error_before += std::abs(off.predict_power(sample.passes) - sample.power_w);
    error_after += std::abs(fit.model.predict_power(sample.passes) - sample.power_w);
  }
  CHECK(error_after < 0.5 * error_before);
  CHECK(held_out_error(fit.model, scene, kMiddle) < held_out_error(off, scene, kMiddle));
  for (const auto& [pass, k] : fitted_of(fit.model)) {
    const PassCoefficients& start = *off.find(pass);
    CHECK(k.k_f == Approx(start.k_f).epsilon(0.5));  // moved, but not off to garbage
  }
}

TEST_CASE("NaN and infinite samples are rejected, the rest is fitted as if they were absent",
          "[model][fit][extremes]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.2);
  const auto clean = window_of(scene, 0, 30, kMiddle);
  auto dirty = clean;
  dirty[2].power_w = std::nan("");
  dirty[5].power_w = std::numeric_limits<double>::infinity();
  dirty[9].passes[3].counts.fragments = std::nan("");
  dirty[11].passes[0].counts.batches = -std::numeric_limits<double>::infinity();
  std::vector<FrameSample> survivors;
  for (std::size_t i = 0; i < clean.size(); ++i) {
    if (i != 2 && i != 5 && i != 9 && i != 11) survivors.push_back(clean[i]);
  }
  const WindowFitResult from_dirty = fit_window(dirty, PowerModel(synthetic_profile()));
  const WindowFitResult from_survivors = fit_window(survivors, PowerModel(synthetic_profile()));
  CHECK(from_dirty.samples_rejected == 4);
  CHECK(from_dirty.samples_used == 26);
  check_same_coefficients(from_dirty.model, from_survivors.model, 1e-12);
}

TEST_CASE("zero counts: an empty window or all-zero frames change nothing", "[model][fit][extremes]") {
  PowerModel previous(synthetic_profile());
  previous.set(0, {1.0, 2.0, 3.0});
  CHECK(fit_window({}, previous).model.find(0)->k_f == 3.0);
  const std::vector<FrameSample> idle(30, FrameSample{20.0, {{0, {0.0, 0.0, 0.0}}}});
  const WindowFitResult fit = fit_window(idle, previous);
  CHECK(fit.columns == 0);
  CHECK(fit.model.find(0)->k_f == 3.0);
}

TEST_CASE("counts near 2^40 fit as well as ordinary ones", "[model][fit][extremes]") {
  // The same scene with every count and every saturation count scaled by 2^40 / 2^20:
  // the normalised problem is identical, so the prediction must be too.
  SceneGenerator scene(six_pass_hidden_model(), 0.1);
  const auto window = window_of(scene, 0, 30, kMiddle);
  const double scale = std::ldexp(1.0, 20);
  PlatformProfile huge = synthetic_profile();
  huge.saturation_batches *= scale * scale * scale;  // batches ~300 -> ~2^40
  huge.saturation_vertices *= scale;
  huge.saturation_fragments *= scale;
  auto scaled = window;
  for (FrameSample& sample : scaled) {
    for (PassFrame& pass : sample.passes) {
      pass.counts.batches *= scale * scale * scale;
      pass.counts.vertices *= scale;
      pass.counts.fragments *= scale;
    }
  }
  CHECK(scaled[0].passes[0].counts.batches > std::ldexp(1.0, 39));
  const WindowFitResult ordinary = fit_window(window, PowerModel(synthetic_profile()));
  const WindowFitResult large = fit_window(scaled, PowerModel(huge));
  for (std::size_t i = 0; i < window.size(); ++i) {
    CHECK(large.model.predict_power(scaled[i].passes) ==
          Approx(ordinary.model.predict_power(window[i].passes)).epsilon(1e-9));
  }
}

TEST_CASE("counts near 2^40 against ordinary saturation counts saturate at P_M", "[model][fit][extremes]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  auto window = window_of(scene, 0, 30, kMiddle);
  for (FrameSample& sample : window) {
    for (PassFrame& pass : sample.passes) pass.counts.fragments = std::ldexp(1.0, 40) - 1.0;
    sample.power_w = 60.0;
  }
  const WindowFitResult fit = fit_window(window, PowerModel(synthetic_profile()));
  for (const FrameSample& sample : window) {
    const double predicted = fit.model.predict_power(sample.passes);
    CHECK(std::isfinite(predicted));
    CHECK(predicted == Approx(60.0).epsilon(2e-3));
  }
}

TEST_CASE("measured power at or above P_M and below P_m stays finite", "[model][fit][extremes]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  SECTION("above P_M") {
    auto window = window_of(scene, 0, 30, kMiddle);
    for (std::size_t i = 0; i < window.size(); ++i) window[i].power_w = 60.0 + static_cast<double>(i);
    const WindowFitResult fit = fit_window(window, PowerModel(synthetic_profile()));
    for (const FrameSample& sample : window) {
      const double predicted = fit.model.predict_power(sample.passes);
      CHECK(std::isfinite(predicted));
      CHECK(predicted > 59.0);
      CHECK(predicted <= 60.0);
    }
  }
  SECTION("below P_m") {
    auto window = window_of(scene, 0, 30, kMiddle);
    for (FrameSample& sample : window) sample.power_w = 5.0;
    const WindowFitResult fit = fit_window(window, PowerModel(synthetic_profile()));
    for (const FrameSample& sample : window) CHECK(fit.model.predict_power(sample.passes) == Approx(20.0));
  }
}

TEST_CASE("P_M = P_m leaves nothing to fit", "[model][fit][extremes]") {
  PlatformProfile flat = synthetic_profile();
  flat.p_max_w = flat.p_min_w;
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  const WindowFitResult fit = fit_window(window_of(scene, 0, 30, kMiddle), PowerModel(flat));
  CHECK(fit.model.fitted_passes() == 0);
  CHECK(fit.model.predict_power(scene.counts(1)) == flat.p_min_w);
}

TEST_CASE("a cost that would be negative is fitted as zero", "[model][fit]") {
  // Power that falls as vertices rise: the unconstrained fit would give k_v < 0.
  PowerModel previous(synthetic_profile());
  std::vector<FrameSample> window;
  for (int t = 0; t < 30; ++t) {
    const double b = 100.0 + 37.0 * (t % 5), v = 1e6 + 2e5 * (t % 7);
    const double alpha = 3.0 * b / 5000.0 - 0.3 * v / 3.0e7;  // > 0 for all these counts
    window.push_back({20.0 + 40.0 * -std::expm1(-alpha), {{0, {b, v, 0.0}}}});
  }
  const WindowFitResult fit = fit_window(window, previous);
  CHECK(fit.model.find(0)->k_v == 0.0);
  CHECK(fit.model.find(0)->k_b > 0.0);
}

TEST_CASE("a window wider than the stack-sized solve (10 passes, 30 columns) is fitted exactly", "[model][fit]") {
  // Up to 24 columns the solve uses fixed-maximum-size storage; wider windows take the
  // dynamic path, which must compute the same regression. Counts drawn independently per
  // pass, term and frame keep all 30 columns identifiable from 60 noiseless frames.
  PowerModel truth(synthetic_profile());
  for (int i = 0; i < 10; ++i) truth.set(static_cast<PassIndex>(i), {0.3 + 0.1 * i, 0.2 + 0.05 * i, 1.0 + 0.2 * i});
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> load(0.5, 1.5);
  std::vector<FrameSample> window;
  for (int t = 0; t < 60; ++t) {
    FrameSample sample;
    for (int i = 0; i < 10; ++i) {
      const double b = 100.0 * load(random), v = 3e5 * load(random), f = 4e6 * load(random);
      sample.passes.push_back({static_cast<PassIndex>(i), {b, v, f}});
    }
    sample.power_w = truth.predict_power(sample.passes);
    window.push_back(sample);
  }
  const WindowFitResult fit = fit_window(window, PowerModel(synthetic_profile()));
  CHECK(fit.columns == 30);
  CHECK(fit.held_terms == 0);
  check_same_coefficients(fit.model, truth, 1e-6);
}
