#pragma once
// A known hidden power model for tests: passes whose coefficients follow paper §5.4 exactly
// (k_v = chi Ins_v, k_f = chi Ins_f + psi Tex_f, per-pass k_b), per-frame counts that drift
// like a camera path, and measured power = the model's power plus Gaussian noise.
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/power_curve.hpp"
#include "glbudget/model/power_model.hpp"

namespace glbudget::model::testing {

inline PlatformProfile synthetic_profile() {
  PlatformProfile profile;
  profile.p_min_w = 20.0;
  profile.p_max_w = 60.0;
  profile.saturation_batches = 5000.0;
  profile.saturation_vertices = 3.0e7;
  profile.saturation_fragments = 4.0e8;
  return profile;
}

// Each pass the model has coefficients for, in index order.
inline std::vector<std::pair<PassIndex, PassCoefficients>> fitted_of(const PowerModel& model) {
  std::vector<std::pair<PassIndex, PassCoefficients>> out;
  for (PassIndex pass = 0; pass < model.coefficients().size(); ++pass)
    if (const PassCoefficients* k = model.find(pass)) out.emplace_back(pass, *k);
  return out;
}

struct HiddenModel {
  double chi = 0.02;
  double psi = 0.3;
  std::vector<double> k_b;  // per pass
  ConfigurationSpace space;

  PassCoefficients coefficients(std::size_t pass, int level) const {
    const VariantCost& cost = space.passes()[pass].levels[static_cast<std::size_t>(level)];
    return {k_b[pass], chi * cost.ins_v, chi * cost.ins_f + psi * cost.tex_f};
  }
  PowerModel fitted_model_for(const Configuration& configuration) const {
    PowerModel model(synthetic_profile());
    for (std::size_t i = 0; i < space.pass_count(); ++i) {
      model.set(static_cast<PassIndex>(i), coefficients(i, configuration[i]));
    }
    return model;
  }
};

// Six passes with three levels each, as in the paper's renderer (729 configurations).
inline HiddenModel six_pass_hidden_model() {
  HiddenModel hidden;
  std::vector<PassVariants> passes;
  const char* names[] = {"resolution", "shading", "reflections", "shadows", "metals", "antialiasing"};
  for (int i = 0; i < 6; ++i) {
    PassVariants pass{names[i], {}, {}};
    for (int level = 0; level < 3; ++level) {
      const double quality = 3.0 - level;  // cheaper with every level
      pass.levels.push_back({20.0 + 4.0 * i, 40.0 * quality + 15.0 * i, 1.0 * quality + (i % 2)});
    }
    passes.push_back(pass);
    hidden.k_b.push_back(0.5 + 0.2 * i);
  }
  hidden.space = ConfigurationSpace(passes);
  return hidden;
}

class SceneGenerator {
 public:
  SceneGenerator(HiddenModel hidden, double noise_w, unsigned seed = 7)
      : hidden_(std::move(hidden)), noise_w_(noise_w), random_(seed) {}

  // Frame `t` along the path: every pass's counts vary smoothly and independently.
  std::vector<PassFrame> counts(int t) {
    std::uniform_real_distribution<double> jitter(0.9, 1.1);
    std::vector<PassFrame> frame;
    for (std::size_t i = 0; i < hidden_.space.pass_count(); ++i) {
      const double phase = 0.05 * t * (1.0 + 0.37 * static_cast<double>(i)) + static_cast<double>(i);
      const double wave = 1.0 + 0.6 * std::sin(phase);
      const double other = 1.0 + 0.5 * std::cos(1.7 * phase + 0.3);
      frame.push_back({static_cast<PassIndex>(i),
                       {std::round(300.0 * wave * jitter(random_)), std::round(1.0e6 * other * jitter(random_)),
                        std::round(2.0e7 * wave * other * jitter(random_))}});
    }
    return frame;
  }

  double true_power(const std::vector<PassFrame>& frame, const Configuration& configuration) const {
    return hidden_.fitted_model_for(configuration).predict_power(frame);
  }

  FrameSample sample(int t, const Configuration& configuration) {
    FrameSample s{0.0, counts(t)};
    std::normal_distribution<double> noise(0.0, noise_w_);
    s.power_w = true_power(s.passes, configuration) + (noise_w_ > 0.0 ? noise(random_) : 0.0);
    return s;
  }

  const HiddenModel& hidden() const { return hidden_; }

 private:
  HiddenModel hidden_;
  double noise_w_;
  std::mt19937_64 random_;
};

}  // namespace glbudget::model::testing
