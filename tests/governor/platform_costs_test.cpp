// The machine's pass-independent costs: the prior they give a pass, their fit from logs of
// several apps, and what they change for the run-time model's first predictions.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>

#include "glbudget/analysis/cost_fit.hpp"
#include "glbudget/model/platform_costs.hpp"
#include "glbudget/model/power_curve.hpp"
#include "glbudget/model/run_time_model.hpp"
#include "synthetic_scene.hpp"

using namespace glbudget::model;
using namespace glbudget::analysis;
using namespace glbudget::model::testing;

namespace {

const PlatformCosts kHidden{0.8, 0.4, 1.5, 0.012, 0.9};

// The power a platform whose passes all cost kHidden draws, plus the app's own load.
double hidden_power(const PlatformProfile& profile, const ConfigurationSpace& space, const ConfiguredSample& s,
                    double app_alpha) {
  PowerModel model = prior_model(profile, kHidden, space, s.configuration, s.sample.passes);
  model.set_frame_alpha(app_alpha);
  return model.predict_power(s.sample.passes);
}

// A second app unlike the six-pass renderer: three passes, other shaders.
ConfigurationSpace three_pass_space() {
  std::vector<PassVariants> passes;
  for (int i = 0; i < 3; ++i) {
    PassVariants pass{"pass" + std::to_string(i), {}, {}};
    for (int level = 0; level < 3; ++level) {
      pass.levels.push_back({8.0 + 6.0 * i + level, 300.0 / (level + 1) + 50.0 * i, 6.0 - 2.0 * level + i});
    }
    passes.push_back(pass);
  }
  return ConfigurationSpace(passes);
}

// Frames of several configurations along a path, drawn with the hidden costs.
std::vector<ConfiguredSample> app_log(const ConfigurationSpace& space, const PlatformProfile& profile, double app_alpha,
                                      double noise_w, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> jitter(0.8, 1.2);
  std::normal_distribution<double> noise(0.0, noise_w);
  std::vector<ConfiguredSample> log;
  for (int run = 0; run < 6; ++run) {
    const Configuration c = space.decode((static_cast<std::size_t>(run) * 97 + 5) % space.size());
    for (int t = 0; t < 40; ++t) {
      ConfiguredSample s{{}, c};
      for (std::size_t i = 0; i < space.pass_count(); ++i) {
        s.sample.passes.push_back({static_cast<PassIndex>(i),
                                   {std::round(200.0 * jitter(random)), std::round(8.0e5 * jitter(random)),
                                    std::round(1.5e7 * jitter(random))}});
      }
      s.sample.power_w = hidden_power(profile, space, s, app_alpha) + (noise_w > 0.0 ? noise(random) : 0.0);
      log.push_back(s);
    }
  }
  return log;
}

}  // namespace

TEST_CASE("a pass's prior coefficients are the platform's costs at its level", "[model][costs]") {
  const PassCoefficients k = prior_coefficients(kHidden, {10.0, 200.0, 4.0});
  CHECK(k.k_b == Approx(0.8));
  CHECK(k.k_v == Approx(0.4 + 0.012 * 10.0));
  CHECK(k.k_f == Approx(1.5 + 0.012 * 200.0 + 0.9 * 4.0));

  // A skipped level is costed as the pass's cheapest drawing level; a pass outside the space
  // as one of no instructions and texels.
  std::vector<PassVariants> passes{
      {"reflections", {{12.0, 600.0, 20.0}, {12.0, 180.0, 8.0}, {0, 0, 0, 1.0, false}}, {}}};
  const ConfigurationSpace space(passes);
  constexpr PassIndex kReflections = 0, kUpscale = 1;  // the space's one pass, and one outside it
  const std::vector<PassFrame> frame{{kReflections, {1, 1, 1}}, {kUpscale, {1, 1, 1}}};
  const PowerModel model = prior_model(synthetic_profile(), kHidden, space, {2}, frame);
  CHECK(model.find(kReflections)->k_f == Approx(1.5 + 0.012 * 180.0 + 0.9 * 8.0));
  CHECK(model.find(kUpscale)->k_f == Approx(1.5));
  CHECK(model.find(kUpscale)->k_v == Approx(0.4));
}

TEST_CASE("the costs fit finds a platform's costs from logs of two apps with loads of their own", "[model][costs]") {
  const PlatformProfile profile = synthetic_profile();
  const ConfigurationSpace six = six_pass_hidden_model().space, three = three_pass_space();
  const double noise_w = GENERATE(0.0, 0.05);
  const auto renderer = app_log(six, profile, 0.05, noise_w, 1);
  const auto other = app_log(three, profile, 0.2, noise_w, 2);
  const CostLog logs[] = {{renderer, &six}, {other, &three}};
  const auto fit = fit_platform_costs(logs, profile);
  REQUIRE(fit);
  CHECK(fit->samples_used == renderer.size() + other.size());
  // Noiseless: exact but for the fit's faint ridge.
  const double tolerance = noise_w > 0.0 ? 0.05 : 1e-5;
  CHECK(fit->costs.batch == Approx(kHidden.batch).epsilon(tolerance * 4));
  CHECK(fit->costs.fragment == Approx(kHidden.fragment).epsilon(tolerance));
  CHECK(fit->costs.instruction == Approx(kHidden.instruction).epsilon(tolerance));
  CHECK(fit->costs.texel == Approx(kHidden.texel).epsilon(tolerance));
  REQUIRE(fit->frame_alpha.size() == 2);
  // An app's own load trades off against the per-draw costs it always draws alike.
  const double load_margin = noise_w > 0.0 ? 0.02 : 1e-5;
  CHECK(fit->frame_alpha[0] == Approx(0.05).margin(load_margin));
  CHECK(fit->frame_alpha[1] == Approx(0.2).margin(load_margin));
  for (std::size_t l = 0; l < 2; ++l) {
    CHECK(fit->per_frame[l].mape_percent() < (noise_w > 0.0 ? 0.5 : 1e-4));
    CHECK(fit->per_configuration[l].count() == 6);
  }
}

TEST_CASE("the costs fit survives the extremes", "[model][costs][extremes]") {
  const PlatformProfile profile = synthetic_profile();
  const ConfigurationSpace six = six_pass_hidden_model().space;
  auto log = app_log(six, profile, 0.05, 0.0, 3);

  SECTION("nothing to fit") {
    CHECK(!fit_platform_costs({}, profile));
    const CostLog no_space[] = {{log, nullptr}};
    CHECK(!fit_platform_costs(no_space, profile));
    PlatformProfile flat = profile;
    flat.p_max_w = flat.p_min_w;
    const CostLog logs[] = {{log, &six}};
    CHECK(!fit_platform_costs(logs, flat));
  }
  SECTION("broken frames are skipped, saturated ones carry no weight") {
    log[3].sample.power_w = std::nan("");
    log[4].sample.passes[1].counts.fragments = INFINITY;
    log[5].sample.power_w = profile.p_max_w * 2.0;  // beyond P_M
    log[6].sample.power_w = profile.p_min_w / 2.0;  // below P_m
    log[7].configuration = {7, 7, 7, 7, 7, 7};      // outside the space
    const CostLog logs[] = {{log, &six}};
    const auto fit = fit_platform_costs(logs, profile);
    REQUIRE(fit);
    CHECK(fit->samples_used == log.size() - 3);
    CHECK(std::isfinite(fit->costs.texel));
    CHECK(fit->costs.fragment >= 0.0);
  }
  SECTION("counts near 2^40 with a profile scaled alike give the same costs") {
    PlatformProfile huge = profile;
    const double factor = std::ldexp(1.0, 40) / 1.5e7;
    huge.saturation_batches *= factor;
    huge.saturation_vertices *= factor;
    huge.saturation_fragments *= factor;
    for (ConfiguredSample& s : log) {
      for (PassFrame& p : s.sample.passes) {
        p.counts.batches *= factor;
        p.counts.vertices *= factor;
        p.counts.fragments *= factor;
      }
    }
    const CostLog logs[] = {{log, &six}};
    const auto fit = fit_platform_costs(logs, huge);
    REQUIRE(fit);
    CHECK(fit->costs.fragment == Approx(kHidden.fragment).epsilon(1e-5));
    CHECK(fit->costs.texel == Approx(kHidden.texel).epsilon(1e-5));
  }
  SECTION("a cost no frame can show stays 0") {
    // No pass samples a texture: the texel cost has nothing to go on.
    std::vector<PassVariants> passes = six.passes();
    for (PassVariants& pass : passes) {
      for (VariantCost& level : pass.levels) level.tex_f = 0.0;
    }
    const ConfigurationSpace untextured(passes);
    for (ConfiguredSample& s : log) s.sample.power_w = hidden_power(profile, untextured, s, 0.05);
    const CostLog logs[] = {{log, &untextured}};
    const auto fit = fit_platform_costs(logs, profile);
    REQUIRE(fit);
    CHECK(fit->costs.texel == 0.0);
    CHECK(fit->costs.instruction == Approx(kHidden.instruction).epsilon(1e-4));
  }
}

TEST_CASE("with calibrated costs the first window predicts other configurations though it cannot tell passes apart",
          "[model][costs][history]") {
  // Every frame of the window draws the same counts (a still camera): the window sees one
  // load and cannot say which pass carries it. Without a prior it spreads the load over the
  // passes; with the platform's costs it keeps their shape and fits their level.
  PlatformProfile calibrated = synthetic_profile();
  calibrated.costs = kHidden;
  const ConfigurationSpace six = six_pass_hidden_model().space;
  const Configuration drawn{0, 0, 0, 0, 0, 0};
  const auto log = app_log(six, calibrated, 0.0, 0.0, 4);
  ConfiguredSample still{log.front().sample, drawn};
  still.sample.power_w = hidden_power(calibrated, six, still, 0.0);

  const auto worst_error = [&](const PlatformProfile& profile) {
    RunTimeModel model(profile, six);
    for (int t = 0; t < 30; ++t) model.learn(still.sample, drawn, model.predict_frame(still.sample, drawn));
    REQUIRE(model.fitted());
    model.predict_frame(still.sample, drawn);
    double worst = 0.0;
    for (std::size_t index = 0; index < six.size(); index += 7) {
      const ConfiguredSample other{still.sample, six.decode(index)};
      const double truth = hidden_power(calibrated, six, other, 0.0);
      worst = std::max(worst, std::abs(model.predict(other.configuration) - truth) / truth);
    }
    return worst;
  };
  const double with_costs = worst_error(calibrated);
  CHECK(with_costs < 0.005);
  CHECK(worst_error(synthetic_profile()) > 10.0 * with_costs);
}
