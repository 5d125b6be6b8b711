#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "glbudget/model/power_curve.hpp"
#include "glbudget/analysis/vatjus_anttila_model.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget::model;
using namespace glbudget::analysis;
using namespace glbudget::model::testing;

TEST_CASE("baseline fits data that follows its own form", "[model][baseline]") {
  const PlatformProfile profile = synthetic_profile();
  std::vector<FrameTotals> frames;
  std::vector<double> power;
  for (int t = 0; t < 30; ++t) {
    const FrameTotals f{1e6 + 1e5 * (t % 7), 500.0 + 40.0 * (t % 5), 5e7 + 1e7 * std::sin(t)};
    const double alpha = 0.5 * f.batches / profile.saturation_batches +
                         3.0 * f.triangles / profile.saturation_vertices +
                         2.0 * f.texels / profile.saturation_fragments;
    frames.push_back(f);
    power.push_back(power_from_alpha(profile, alpha));
  }
  VatjusAnttilaModel baseline(profile);
  CHECK(!baseline.fitted());
  baseline.fit(frames, power);
  CHECK(baseline.fitted());
  for (std::size_t i = 0; i < frames.size(); ++i) {
    CHECK(baseline.predict_power(frames[i]) == Approx(power[i]).epsilon(1e-6));
  }
}

TEST_CASE("baseline cannot follow per-pass costs the way the per-pass model does", "[model][baseline]") {
  // Two passes with very different fragment costs whose shares of the frame change: one
  // weighted sum of texels cannot represent that.
  const PlatformProfile profile = synthetic_profile();
  std::vector<FrameTotals> frames;
  std::vector<double> power;
  for (int t = 0; t < 60; ++t) {
    const double cheap = 2e7 * (1.0 + std::sin(0.2 * t)), expensive = 2e7 * (1.0 + std::cos(0.2 * t));
    frames.push_back({1e6, 400.0, cheap + expensive});
    power.push_back(power_from_alpha(profile, (0.5 * cheap + 6.0 * expensive) / profile.saturation_fragments));
  }
  VatjusAnttilaModel baseline(profile);
  baseline.fit(std::span(frames).first(30), std::span(power).first(30));
  double error = 0.0;
  for (std::size_t i = 30; i < frames.size(); ++i) error += std::abs(baseline.predict_power(frames[i]) - power[i]);
  CHECK(error / 30.0 > 0.02 * profile.range_w());
}
