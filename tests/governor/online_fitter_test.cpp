#include <catch2/catch.hpp>

#include <cmath>

#include "glbudget/model/online_fitter.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget::model;
using namespace glbudget::model::testing;

namespace {
const Configuration kBest{0, 0, 0, 0, 0, 0};

double predict_or_nan(const OnlineFitter& fitter, const FrameSample& sample) {
  return fitter.has_model() ? fitter.model().predict_power(sample.passes) : std::nan("");
}
}  // namespace

TEST_CASE("online fitter fits after the fitting window, then checks", "[model][online]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.2);
  OnlineFitter fitter(synthetic_profile());
  for (int t = 0; t < 29; ++t) {
    const FrameSample s = scene.sample(t, kBest);
    CHECK(fitter.add_frame(s, predict_or_nan(fitter, s)) == OnlineFitter::Event::None);
  }
  CHECK(!fitter.has_model());
  const FrameSample last = scene.sample(29, kBest);
  CHECK(fitter.add_frame(last, predict_or_nan(fitter, last)) == OnlineFitter::Event::Fitted);
  CHECK(fitter.phase() == OnlineFitter::Phase::Checking);
  CHECK(fitter.last_window_mean().size() == 6);

  int passed = 0;
  for (int t = 30; t < 130; ++t) {
    const FrameSample s = scene.sample(t, kBest);
    const auto event = fitter.add_frame(s, predict_or_nan(fitter, s));
    CHECK(event != OnlineFitter::Event::CheckFailed);
    passed += event == OnlineFitter::Event::CheckPassed;
  }
  CHECK(passed == 10);
  CHECK(fitter.fits() == 1);
}

TEST_CASE("online fitter refits when the scene outgrows the model", "[model][online]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  FitSettings settings;
  settings.fitting_window = 20;
  settings.check_window = 5;
  settings.refit_threshold = 0.02;
  OnlineFitter fitter(synthetic_profile(), settings);
  for (int t = 0; t < 20; ++t) fitter.add_frame(scene.sample(t, kBest), std::nan(""));
  REQUIRE(fitter.fits() == 1);

  // Every pass now costs twice as much (say, a heavier material everywhere).
  auto heavier = [&](int t) {
    FrameSample s = scene.sample(t, kBest);
    const double alpha = 2.0 * scene.hidden().fitted_model_for(kBest).alpha(s.passes);
    s.power_w = power_from_alpha(synthetic_profile(), alpha);
    return s;
  };
  std::vector<OnlineFitter::Event> events;
  for (int t = 20; t < 45; ++t) {
    const FrameSample s = heavier(t);
    events.push_back(fitter.add_frame(s, predict_or_nan(fitter, s)));
  }
  CHECK(events[4] == OnlineFitter::Event::CheckFailed);
  CHECK(events[24] == OnlineFitter::Event::Fitted);
  CHECK(fitter.fits() == 2);
  const FrameSample later = heavier(300);
  CHECK(fitter.model().predict_power(later.passes) == Approx(later.power_w).epsilon(1e-3));
}

TEST_CASE("online fitter ignores broken frames and restarts windows on configuration change",
          "[model][online][extremes]") {
  SceneGenerator scene(six_pass_hidden_model(), 0.0);
  FitSettings settings;
  settings.fitting_window = 10;
  OnlineFitter fitter(synthetic_profile(), settings);
  FrameSample broken = scene.sample(0, kBest);
  broken.power_w = std::nan("");
  CHECK(fitter.add_frame(broken, 0.0) == OnlineFitter::Event::Rejected);
  for (int t = 0; t < 9; ++t) fitter.add_frame(scene.sample(t, kBest), std::nan(""));
  fitter.configuration_changed();  // before the first fit: window restarts
  CHECK(fitter.phase() == OnlineFitter::Phase::Fitting);
  for (int t = 0; t < 9; ++t) {
    CHECK(fitter.add_frame(scene.sample(t, kBest), std::nan("")) == OnlineFitter::Event::None);
  }
  CHECK(fitter.add_frame(scene.sample(9, kBest), std::nan("")) == OnlineFitter::Event::Fitted);
  // As in the paper, a new configuration starts a new fitting window.
  fitter.configuration_changed();
  CHECK(fitter.phase() == OnlineFitter::Phase::Fitting);

  settings.refit_on_change = false;
  OnlineFitter checking_first(synthetic_profile(), settings);
  for (int t = 0; t < 10; ++t) checking_first.add_frame(scene.sample(t, kBest), std::nan(""));
  REQUIRE(checking_first.has_model());
  checking_first.configuration_changed();
  CHECK(checking_first.phase() == OnlineFitter::Phase::Checking);
  const FrameSample s = scene.sample(10, kBest);
  CHECK(checking_first.add_frame(s, std::nan("")) == OnlineFitter::Event::Rejected);  // no prediction to check
}
