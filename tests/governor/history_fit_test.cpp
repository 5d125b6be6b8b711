// The fit over several configurations (history_fit.hpp) and the run-time model that uses it.
#include <catch2/catch.hpp>

#include <cmath>

#include "glbudget/model/history_fit.hpp"
#include "glbudget/model/run_time_model.hpp"
#include "glbudget/model/window_fit.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget::model;
using namespace glbudget::model::testing;

namespace {

// The hidden model of synthetic_scene.hpp plus a per-fragment cost of every pass that no
// instruction or texel explains (rasterisation, blending): what one configuration's chi and
// psi regression cannot separate from the shader's costs.
struct Truth {
  HiddenModel hidden;
  double operator()(const std::vector<PassFrame>& frame, const Configuration& c) const {
    PowerModel model = hidden.fitted_model_for(c);
    for (std::size_t i = 0; i < hidden.space.pass_count(); ++i) {
      PassCoefficients k = hidden.coefficients(i, c[i]);
      k.k_f += 2.0 + 3.0 * static_cast<double>(i % 3);
      model.set(static_cast<PassIndex>(i), k);
    }
    return model.predict_power(frame);
  }
};

// A view that barely moves: every frame of a configuration has the same counts up to 0.1%,
// and the sensor's noise (noise_w) hides what that little variation would tell, so one
// configuration's window cannot tell a pass's terms apart.
std::vector<ConfiguredSample> steady_history(SceneGenerator& scene, const Truth& truth,
                                             const std::vector<Configuration>& visited, int frames_each,
                                             double noise_w = 0.0) {
  std::mt19937_64 random(11);
  std::normal_distribution<double> noise(0.0, noise_w > 0.0 ? noise_w : 1.0);
  std::vector<ConfiguredSample> history;
  int t = 0;
  for (const Configuration& c : visited) {
    for (int f = 0; f < frames_each; ++f, ++t) {
      FrameSample s = scene.sample(0, c);
      std::vector<PassFrame> counts = s.passes;
      for (PassFrame& p : counts) {
        const double wobble = 1.0 + 0.001 * std::sin(0.7 * t + p.counts.batches);
        p.counts.fragments = std::round(p.counts.fragments * wobble);
      }
      const double power = truth(counts, c) + (noise_w > 0.0 ? noise(random) : 0.0);
      history.push_back({{power, counts}, c});
    }
  }
  return history;
}

double mape_over_space(const ConfigurationSpace& space, const Truth& truth, const std::vector<PassFrame>& frame,
                       const ConfigurationPredictor& predictor) {
  std::vector<double> all;
  predictor.predict_all(all);
  double sum = 0.0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    const double expected = truth(frame, space.decode(i));
    sum += std::abs(all[i] - expected) / expected;
  }
  return 100.0 * sum / static_cast<double>(all.size());
}

}  // namespace

TEST_CASE("a fit over four configurations of a steady view predicts all 729", "[model][history]") {
  const HiddenModel hidden = six_pass_hidden_model();
  SceneGenerator scene(hidden, 0.0);
  const std::vector<Configuration> visited{
      {0, 0, 0, 0, 0, 0}, {2, 1, 0, 2, 1, 0}, {1, 2, 2, 0, 0, 1}, {0, 1, 2, 1, 2, 2}};
  const Truth truth{hidden};
  const std::vector<ConfiguredSample> history = steady_history(scene, truth, visited, 30, /*noise_w=*/0.2);
  const Configuration here = visited.back();
  const auto fit = fit_history(history, hidden.space, PowerModel(synthetic_profile()), here, {}, here);
  REQUIRE(fit);
  CHECK(fit->configurations == 4);
  CHECK(fit->samples_used == 120);
  // In this hidden model a level's instructions and texels per fragment fall together
  // (40 instructions per texel), so only 40 chi + psi is identifiable.
  CHECK(40.0 * fit->reuse.chi + fit->reuse.psi == Approx(40.0 * hidden.chi + hidden.psi).epsilon(0.05));

  ConfigurationPredictor predictor(hidden.space, fit->model, here, fit->reuse);
  const std::vector<PassFrame> frame = history.back().sample.passes;
  predictor.set_frame(frame, here);
  const double history_mape = mape_over_space(hidden.space, truth, frame, predictor);
  CHECK(history_mape < 1.5);  // 0.2 W of noise on 20..60 W

  // The paper's path on the same frames: one configuration's window, chi and psi from it.
  const std::vector<FrameSample> window = [&] {
    std::vector<FrameSample> w;
    for (std::size_t i = history.size() - 30; i < history.size(); ++i) w.push_back(history[i].sample);
    return w;
  }();
  const PowerModel windowed = fit_window(window, PowerModel(synthetic_profile())).model;
  const ReuseCoefficients reuse = solve_reuse(windowed, hidden.space, here, window.back().passes);
  ConfigurationPredictor paper(hidden.space, windowed, here, reuse);
  paper.set_frame(frame, here);
  const double paper_mape = mape_over_space(hidden.space, truth, frame, paper);
  INFO("history " << history_mape << "% against one window " << paper_mape << "%");
  CHECK(history_mape < paper_mape);
}

TEST_CASE("a history of one configuration still fits that configuration", "[model][history][extremes]") {
  const HiddenModel hidden = six_pass_hidden_model();
  SceneGenerator scene(hidden, 0.0);
  const Configuration only{1, 1, 1, 1, 1, 1};
  const std::vector<ConfiguredSample> history = steady_history(scene, Truth{hidden}, {only}, 40);
  const auto fit = fit_history(history, hidden.space, PowerModel(synthetic_profile()), only, {0.5, 0.25}, only);
  REQUIRE(fit);
  CHECK(fit->configurations == 1);
  // chi and psi are collinear with the passes' own columns here: the ridge settles them
  // (the run-time model only fits histories of several configurations), finite and >= 0.
  CHECK(std::isfinite(fit->reuse.chi));
  CHECK(fit->reuse.chi >= 0.0);
  CHECK(fit->reuse.psi >= 0.0);
  // The fitted configuration itself is predicted exactly.
  ConfigurationPredictor predictor(hidden.space, fit->model, only, fit->reuse);
  predictor.set_frame(history.back().sample.passes, only);
  CHECK(predictor.predict(only) == Approx(history.back().sample.power_w).epsilon(1e-3));
}

TEST_CASE("the history fit ignores broken samples and refuses what it cannot use", "[model][history][extremes]") {
  const HiddenModel hidden = six_pass_hidden_model();
  SceneGenerator scene(hidden, 0.0);
  const Configuration c{0, 0, 0, 0, 0, 0};
  std::vector<ConfiguredSample> history = steady_history(scene, Truth{hidden}, {c, {2, 2, 2, 2, 2, 2}}, 20);
  const PowerModel prior(synthetic_profile());
  history[3].sample.power_w = std::nan("");
  history[4].sample.passes[0].counts.fragments = INFINITY;
  history[5].configuration = {7, 0, 0, 0, 0, 0};  // not in the space
  history[6].sample.power_w = 1e9;                // far above P_M: clamped, nearly weightless
  history[7].sample.power_w = -5.0;               // below P_m
  const auto fit = fit_history(history, hidden.space, prior, c, {}, c);
  REQUIRE(fit);
  CHECK(fit->samples_used == 37);
  for (const auto& [pass, k] : fitted_of(fit->model)) {
    CHECK(std::isfinite(k.k_b));
    CHECK(k.k_f >= 0.0);
  }
  CHECK(!fit_history({}, hidden.space, prior, c, {}, c));
  CHECK(!fit_history(history, hidden.space, prior, c, {}, {9, 9, 9, 9, 9, 9}));
  PlatformProfile flat = synthetic_profile();
  flat.p_max_w = flat.p_min_w;  // P_M = P_m: nothing to fit
  CHECK(!fit_history(history, hidden.space, PowerModel(flat), c, {}, c));
}

TEST_CASE("the run-time model fits, refits after each change and then knows every configuration it saw",
          "[model][history]") {
  const HiddenModel hidden = six_pass_hidden_model();
  SceneGenerator scene(hidden, 0.05);
  RunTimeModel model(synthetic_profile(), hidden.space);
  const Configuration a{0, 0, 0, 0, 0, 0}, b{2, 1, 0, 2, 1, 0}, unseen{1, 2, 1, 0, 2, 2};
  int t = 0;
  for (; t < 30; ++t) {
    const FrameSample s = scene.sample(t, a);
    const double predicted = model.predict_frame(s, a);
    CHECK(std::isnan(predicted) == (t < 30));
    model.learn(s, a, predicted);
  }
  CHECK(model.fitted());
  CHECK(model.fits() == 1);
  CHECK(model.history_fits() == 0);
  CHECK(model.has_data_for(a));
  CHECK(!model.has_data_for(b));
  for (; t < 60; ++t) {
    const FrameSample s = scene.sample(t, b);
    model.learn(s, b, model.predict_frame(s, b));
  }
  CHECK(model.fits() == 2);
  CHECK(model.history_fits() == 1);
  CHECK(model.has_data_for(a));
  CHECK(model.has_data_for(b));
  const FrameSample s = scene.sample(60, b);
  model.predict_frame(s, b);
  CHECK(model.predict(unseen) == Approx(scene.true_power(s.passes, unseen)).epsilon(0.02));
  std::vector<double> all;
  model.predict_all(all);
  CHECK(all[hidden.space.index_of(unseen)] == Approx(model.predict(unseen)).epsilon(1e-12));
  CHECK(std::isnan(model.predict({5, 5, 5, 5, 5, 5})));
}

TEST_CASE("the history fit stays exact for counts near 2^40 and windows of identical frames",
          "[model][history][extremes]") {
  const HiddenModel hidden = six_pass_hidden_model();
  SceneGenerator scene(hidden, 0.0);
  const Truth truth{hidden};
  const Configuration a{0, 0, 0, 0, 0, 0}, b{2, 1, 0, 2, 1, 0};
  // Counts scaled up to ~2^40 with a profile scaled alike: the same loads, so the same powers.
  PlatformProfile huge = synthetic_profile();
  const double factor = std::ldexp(1.0, 40) / 2e7;
  huge.saturation_batches *= factor;
  huge.saturation_vertices *= factor;
  huge.saturation_fragments *= factor;
  std::vector<ConfiguredSample> history;
  for (const Configuration& c : {a, b}) {
    // Every frame of a configuration identical: nothing varies within a configuration.
    FrameSample s = scene.sample(3, c);
    const double power = truth(s.passes, c);
    for (PassFrame& p : s.passes) {
      p.counts.batches *= factor;
      p.counts.vertices *= factor;
      p.counts.fragments *= factor;
    }
    s.power_w = power;
    for (int f = 0; f < 30; ++f) history.push_back({s, c});
  }
  const auto fit = fit_history(history, hidden.space, PowerModel(huge), a, {}, b);
  REQUIRE(fit);
  for (const auto& [pass, k] : fitted_of(fit->model)) {
    CHECK(std::isfinite(k.k_b));
    CHECK(std::isfinite(k.k_v));
    CHECK(std::isfinite(k.k_f));
  }
  ConfigurationPredictor predictor(hidden.space, fit->model, b, fit->reuse);
  for (const ConfiguredSample* s : {&history.front(), &history.back()}) {
    predictor.set_frame(s->sample.passes, s->configuration);
    CHECK(predictor.predict(s->configuration) == Approx(s->sample.power_w).epsilon(1e-3));
  }
}

TEST_CASE("the run-time model takes broken frames and unknown configurations without harm",
          "[model][history][extremes]") {
  const HiddenModel hidden = six_pass_hidden_model();
  SceneGenerator scene(hidden, 0.05);
  RunTimeModel model(synthetic_profile(), hidden.space);
  const Configuration a{0, 0, 0, 0, 0, 0}, outside{3, 0, 0, 0, 0, 0};
  std::vector<double> all;
  model.predict_all(all);
  REQUIRE(all.size() == hidden.space.size());
  CHECK(std::isnan(all[0]));  // nothing fitted yet
  for (int t = 0; t < 30; ++t) {
    FrameSample s = scene.sample(t, a);
    if (t % 7 == 3) s.power_w = std::nan("");             // the sensor gave nothing
    if (t % 7 == 5) s.passes[2].counts.fragments = -1.0;  // a broken count
    model.learn(s, a, model.predict_frame(s, a));
  }
  CHECK(!model.fitted());  // broken frames do not count towards the window
  for (int t = 30; t < 40; ++t) {
    const FrameSample s = scene.sample(t, a);
    model.learn(s, a, model.predict_frame(s, a));
  }
  REQUIRE(model.fitted());
  // A frame drawn in a configuration outside the space is predicted as the fitted one and
  // kept out of the history; predictions for it are NaN.
  const FrameSample s = scene.sample(41, a);
  CHECK(std::isfinite(model.predict_frame(s, outside)));
  CHECK(std::isnan(model.predict(outside)));
  model.learn(s, outside, std::nan(""));
  CHECK(!model.has_data_for(outside));
  model.predict_frame(s, a);
  model.predict_all(all);
  for (double p : all) {
    CHECK(std::isfinite(p));
    CHECK(p >= synthetic_profile().p_min_w);
    CHECK(p <= synthetic_profile().p_max_w);
  }
}
