#pragma once
// Reusing one fitted configuration for all others (paper §5.4):
//   k_vi(s_i) = chi * Ins_vi(s_i),  k_fi(s_i) = chi * Ins_fi(s_i) + psi * Tex_fi(s_i),
// k_bi unchanged. chi and psi come from a regression over the fitted configuration's passes.
//
// The regression weights each pass's equations by that pass's mean normalised vertex and
// fragment counts in the fitting window, so chi and psi are accurate where they matter for
// power. Predictions apply chi and psi to the *difference* from the fitted level, so the
// fitted configuration is predicted exactly as fitted and per-pass costs that are not
// proportional to instructions or texels (raster, blending) carry over to other levels.
#include <cstddef>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/fragment_scales.hpp"
#include "glbudget/model/power_model.hpp"

namespace glbudget::model {

struct ReuseCoefficients {
  double chi = 0.0;  // cost of one instruction
  double psi = 0.0;  // cost of one texel access
};

// `previous` is kept for a coefficient the fitted configuration cannot identify (e.g. psi
// when no pass samples textures).
ReuseCoefficients solve_reuse(const PowerModel& fitted, const ConfigurationSpace& space,
                              const Configuration& fitted_configuration, const std::vector<PassFrame>& window_mean,
                              ReuseCoefficients previous = {});

// The least instructions and texel accesses among a pass's levels that draw (each taken
// separately): the base the costs of the other levels are measured from.
VariantCost cheapest_drawing_level(const PassVariants& pass);

// Predicts the power of every configuration for the counts of one frame.
//
// Counts are measured in the frame's own configuration. Levels that scale fragments (render
// scale, shadow-map size) turn them into reference counts (all scales at 1) and back into each
// configuration's counts; a pass whose level skips it (reflections off) is predicted from the
// counts it drew the last time it was on.
class ConfigurationPredictor {
 public:
  ConfigurationPredictor(const ConfigurationSpace& space, const PowerModel& fitted,
                         const Configuration& fitted_configuration, ReuseCoefficients reuse);

  // New coefficients after a refit; the remembered counts of skipped passes are kept.
  void refit(const PowerModel& fitted, const Configuration& fitted_configuration, ReuseCoefficients reuse);

  PassCoefficients coefficients(std::size_t pass, int level) const;

  // Measured fragment scales in place of the table's declared ones, from the next
  // set_frame() on (fragment_scales.hpp).
  void set_fragment_scales(FragmentScales scales) { scales_ = std::move(scales); }

  // Per-pass, per-level loads for a frame drawn in `frame_configuration`. Counts of passes
  // outside the space (say the fixed-function pass) add the same load to every configuration.
  void set_frame(const std::vector<PassFrame>& frame, const Configuration& frame_configuration);
  // The frame was drawn in the fitted configuration.
  void set_frame(const std::vector<PassFrame>& frame) { set_frame(frame, fitted_configuration_); }

  // NaN for a configuration outside the space.
  double predict(const Configuration& configuration) const;
  // out[space.index_of(c)] = predicted power of c.
  void predict_all(std::vector<double>& out) const;

 private:
  // Reference counts of a pass: fragments as if every scale were 1.
  struct ReferenceCounts {
    PassCounts counts;
    bool known = false;
  };
  // One selectable level of a pass in an enumeration: its m = expm1(-alpha), e = exp(-alpha)
  // and its contribution to the configuration's index.
  struct LevelTerm {
    double alpha = 0.0, m = 0.0, e = 1.0;
    std::size_t offset = 0;
  };

  double fragment_scale(std::size_t pass, const Configuration& configuration) const;
  std::size_t outer_combination(const Configuration& configuration) const;
  // q = prod(1 + m) - 1 (starting from q0), e = prod e and the index offset for every
  // combination of the levels of passes [first, last), in row-major order; a pass with
  // held[pass] >= 0 takes only that level. The buffers are kept between calls.
  struct Enumeration {
    std::vector<double> q, e, next_q, next_e;
    std::vector<std::size_t> offsets, next_offsets;
  };
  static void enumerate(const std::vector<std::vector<LevelTerm>>& passes, const std::vector<int>& held,
                        std::size_t first, std::size_t last, double q0, Enumeration& out);

  ConfigurationSpace space_;
  PowerModel fitted_;
  Configuration fitted_configuration_;
  std::vector<std::vector<PassCoefficients>> coefficients_;  // [pass][level]
  std::vector<std::vector<std::size_t>> scalers_of_;         // [pass]: passes scaling its fragments
  FragmentScales scales_;
  std::vector<std::size_t> outer_;           // passes that scale other passes' fragments
  std::vector<bool> scaled_by_outer_;        // [pass]: one of them scales its fragments
  bool outer_is_prefix_ = true;              // they are the first passes of the space
  std::vector<std::size_t> strides_;         // index_of strides
  std::vector<ReferenceCounts> reference_;   // [pass] for the current frame
  std::vector<ReferenceCounts> remembered_;  // [pass] when it last drew
  // [outer combination][pass][level]: the pass's load for the frame with the outer passes at
  // that combination's levels (one combination when no pass scales another).
  std::vector<std::vector<std::vector<LevelTerm>>> tables_;
  double alpha_outside_space_ = 0.0;
  // Scratch space of predict_all(), so that it allocates nothing once warm.
  mutable Enumeration front_, back_;
  mutable std::vector<int> held_scratch_;
};

}  // namespace glbudget::model
