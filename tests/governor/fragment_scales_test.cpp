// Measured fragment scales: what a pass really draws at each level of the pass scaling it.
#include <catch2/catch.hpp>

#include <cmath>

#include "glbudget/model/fragment_scales.hpp"
#include "glbudget/model/reuse.hpp"
#include "glbudget/model/run_time_model.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget::model;
using namespace glbudget::model::testing;

namespace {

// A render scale (area 1, 0.64, 0.36) over a scene pass, and a shadow map scaling itself.
constexpr PassIndex kScene = 1, kShadows = 2;
ConfigurationSpace fragment_scales_space() {
  std::vector<PassVariants> passes;
  passes.push_back({"resolution", {{0, 0, 0, 1.0}, {0, 0, 0, 0.64}, {0, 0, 0, 0.36}}, {"scene"}});
  passes.push_back({"scene", {{10, 100, 2}, {10, 50, 1}}, {}});
  passes.push_back({"shadows", {{10, 0, 0, 1.0}, {10, 0, 0, 0.25}}, {"shadows"}});
  return ConfigurationSpace(passes);
}

ConfiguredSample frame(const Configuration& c, double scene_fragments, double shadow_fragments) {
  return {{15.0, {{kScene, {10, 1000, scene_fragments}}, {kShadows, {5, 500, shadow_fragments}}}}, c};
}

}  // namespace

TEST_CASE("fragment scales start as declared and take the measured ratio of a level seen often enough",
          "[model][scales]") {
  const ConfigurationSpace space = fragment_scales_space();
  const FragmentScales declared(space);
  CHECK(declared.at(1, 0, 1) == 0.64);
  CHECK(declared.at(2, 2, 1) == 0.25);
  CHECK(declared.at(1, 2, 1) == 1.0);  // the shadow map does not scale the scene
  CHECK(!declared.measured(1, 0, 2));

  std::vector<ConfiguredSample> history;
  for (int t = 0; t < 10; ++t) history.push_back(frame({0, 0, 0}, 1000.0 + t, 4000.0));
  for (int t = 0; t < 10; ++t) history.push_back(frame({2, 0, 1}, 480.0 + 0.48 * t, 1200.0));
  for (int t = 0; t < 4; ++t) history.push_back(frame({1, 0, 0}, 10.0, 4000.0));  // too few to measure
  const FragmentScales measured = measure_fragment_scales(history, space, 5);
  CHECK(measured.at(1, 0, 0) == 1.0);  // the anchor keeps its declared scale
  CHECK(measured.at(1, 0, 2) == Approx(0.48));
  CHECK(measured.measured(1, 0, 2));
  CHECK(measured.at(1, 0, 1) == 0.64);  // four frames: still declared
  CHECK(measured.at(2, 2, 1) == Approx(0.3));

  // Without the full-scale level, the largest measured level anchors at its declared scale.
  std::vector<ConfiguredSample> low(history.begin() + 10, history.begin() + 20);
  for (int t = 0; t < 10; ++t) low.push_back(frame({1, 0, 1}, 770.0, 1200.0));
  const FragmentScales anchored = measure_fragment_scales(low, space, 5);
  CHECK(anchored.at(1, 0, 1) == 0.64);
  CHECK(anchored.at(1, 0, 2) == Approx(0.64 * 482.16 / 770.0));
}

TEST_CASE("a level the history no longer holds keeps the scale measured while it did", "[model][scales]") {
  // The demo's Valley: the shadow map at its smallest draws 0.147 of the fragments at its
  // largest, not the declared 0.25 here; the app then stays at the smallest level.
  const ConfigurationSpace space = fragment_scales_space();
  std::vector<ConfiguredSample> both;
  for (int t = 0; t < 10; ++t) both.push_back(frame({0, 0, 0}, 1000.0, 4000.0));
  for (int t = 0; t < 10; ++t) both.push_back(frame({0, 0, 1}, 1000.0, 588.0));
  const FragmentScales known = measure_fragment_scales(both, space, 5);
  REQUIRE(known.at(2, 2, 1) == Approx(0.147));

  std::vector<ConfiguredSample> small(both.begin() + 10, both.end());
  // Forgetting: the smallest level anchors at its declared area, 1.7 times what it draws.
  CHECK(measure_fragment_scales(small, space, 5).at(2, 2, 1) == 0.25);
  // Remembering: it keeps what was measured, and so does every level the history lacks.
  const FragmentScales kept = measure_fragment_scales(small, space, 5, &known);
  CHECK(kept.at(2, 2, 1) == Approx(0.147));
  CHECK(kept.at(2, 2, 0) == 1.0);
  CHECK(kept.at(1, 0, 2) == 0.36);  // never measured: declared

  // A level measured afresh against an anchor known from before is scaled by the anchor's known
  // scale: the render scale at 60 % against 80 %, which was measured at 0.77 of full scale.
  std::vector<ConfiguredSample> render;
  for (int t = 0; t < 10; ++t) render.push_back(frame({0, 0, 0}, 1000.0, 4000.0));
  for (int t = 0; t < 10; ++t) render.push_back(frame({1, 0, 0}, 770.0, 4000.0));
  const FragmentScales at_80 = measure_fragment_scales(render, space, 5, &kept);
  REQUIRE(at_80.at(1, 0, 1) == Approx(0.77));
  std::vector<ConfiguredSample> lower(render.begin() + 10, render.end());
  for (int t = 0; t < 10; ++t) lower.push_back(frame({2, 0, 0}, 370.0, 4000.0));
  const FragmentScales at_60 = measure_fragment_scales(lower, space, 5, &at_80);
  CHECK(at_60.at(1, 0, 1) == Approx(0.77));
  CHECK(at_60.at(1, 0, 2) == Approx(0.77 * 370.0 / 770.0));
  CHECK(at_60.at(2, 2, 1) == Approx(0.147));  // the shadow map's, carried through both
}

TEST_CASE("the run-time model keeps a measured scale after its level's frames leave the history", "[model][scales]") {
  // The app draws the shadow map at full size, then at its smallest for longer than the history
  // holds: predicted from a frame at the smallest, the full-size configuration's shadow pass is
  // still the fragments it drew, not the declared area's 1.7 times them.
  const ConfigurationSpace space = fragment_scales_space();
  HistorySettings history;
  history.frames = 40;
  RunTimeModel model(synthetic_profile(), space, {}, history);
  auto feed = [&](const ConfiguredSample& s) {
    const double predicted = model.predict_frame(s.sample, s.configuration);
    model.learn(s.sample, s.configuration, predicted);
  };
  // Above the synthetic profile's idle of 20 W: the full-size shadow map costs 8 W more.
  for (int t = 0; t < 60; ++t) {
    ConfiguredSample full = frame({0, 0, 0}, 1.0e6 + 1e4 * (t % 7), 4.0e6);
    full.sample.power_w = 40.0 + 0.01 * (t % 7);
    feed(full);
  }
  ConfiguredSample small = frame({0, 0, 1}, 1.0e6, 5.88e5);
  small.sample.power_w = 32.0;
  for (int t = 0; t < 80; ++t) feed(small);
  REQUIRE(model.fitted());
  model.refresh_fragment_scales();
  model.predict_frame(small.sample, small.configuration);
  const ConfiguredSample full = frame({0, 0, 0}, 1.0e6, 4.0e6);
  const ConfigurationPredictor* at_full = model.predictor_for(full.sample, full.configuration);
  REQUIRE(at_full != nullptr);
  const double drawn_at_full = at_full->predict({0, 0, 0});
  model.predict_frame(small.sample, small.configuration);
  // Forgetting the measured scale predicted 36.5 W here, against 40.0 W for the same counts.
  CHECK(model.predict({0, 0, 0}) == Approx(drawn_at_full).epsilon(1e-9));
}

TEST_CASE("fragment scales ignore frames that cannot tell and passes scaled twice", "[model][scales][extremes]") {
  std::vector<PassVariants> passes;
  passes.push_back({"resolution", {{0, 0, 0, 1.0}, {0, 0, 0, 0.25}}, {"scene"}});
  passes.push_back({"scene", {{10, 100, 2}, {0, 0, 0, 1.0, false}}, {"scene"}});  // scaled twice; a level that skips it
  const ConfigurationSpace twice(passes);
  std::vector<ConfiguredSample> history;
  for (int t = 0; t < 10; ++t) {
    history.push_back({{15.0, {{kScene, {1, 1, 1000.0}}}}, {0, 0}});
    history.push_back({{15.0, {{kScene, {1, 1, 500.0}}}}, {1, 0}});
  }
  CHECK(!measure_fragment_scales(history, twice, 5).measured(1, 0, 1));

  const ConfigurationSpace space = fragment_scales_space();
  std::vector<ConfiguredSample> broken;
  for (int t = 0; t < 10; ++t) {
    broken.push_back(frame({0, 0, 0}, 1000.0, 4000.0));
    broken.push_back(frame({2, 0, 0}, std::nan(""), 4000.0));  // not measured
    broken.push_back(frame({2, 0, 0}, 0.0, 4000.0));           // drew nothing
    broken.push_back(frame({7, 0, 0}, 10.0, 4000.0));          // outside the space
  }
  const FragmentScales scales = measure_fragment_scales(broken, space, 5);
  CHECK(!scales.measured(1, 0, 2));
  CHECK(scales.at(1, 0, 2) == 0.36);
  CHECK(measure_fragment_scales({}, space).at(1, 0, 2) == 0.36);
}

TEST_CASE("the predictor converts counts between levels with the measured scales", "[model][scales]") {
  const ConfigurationSpace space = fragment_scales_space();
  PowerModel model(synthetic_profile());
  model.set(kScene, {0.0, 0.0, 50.0});
  model.set(kShadows, {0.0, 0.0, 10.0});
  ConfigurationPredictor predictor(space, model, {2, 0, 0}, {});
  // A frame at render scale 0.6 drew 480 fragments where full scale draws 1000.
  const std::vector<PassFrame> counts{{kScene, {10, 1000, 4.8e6}}, {kShadows, {5, 500, 1.0e6}}};
  FragmentScales scales(space);
  scales.set(1, 0, 2, 0.48);
  predictor.set_fragment_scales(scales);
  predictor.set_frame(counts, {2, 0, 0});
  PowerModel full = model;
  const std::vector<PassFrame> at_full{{kScene, {10, 1000, 1.0e7}}, {kShadows, {5, 500, 1.0e6}}};
  CHECK(predictor.predict({0, 0, 0}) == Approx(full.predict_power(at_full)).epsilon(1e-12));
  // With the declared area the same frame would claim 4.8e6 / 0.36 fragments at full scale.
  predictor.set_fragment_scales(FragmentScales(space));
  predictor.set_frame(counts, {2, 0, 0});
  const std::vector<PassFrame> by_area{{kScene, {10, 1000, 4.8e6 / 0.36}}, {kShadows, {5, 500, 1.0e6}}};
  CHECK(predictor.predict({0, 0, 0}) == Approx(full.predict_power(by_area)).epsilon(1e-12));
}
