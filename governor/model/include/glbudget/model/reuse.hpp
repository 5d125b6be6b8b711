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
#include "glbudget/model/power_model.hpp"

namespace glbudget::model {

struct ReuseCoefficients {
    double chi = 0.0;  // cost of one instruction
    double psi = 0.0;  // cost of one texel access
};

// `previous` is kept for a coefficient the fitted configuration cannot identify (e.g. psi
// when no pass samples textures).
ReuseCoefficients solve_reuse(const PowerModel& fitted, const ConfigurationSpace& space,
                              const Configuration& fitted_configuration,
                              const std::vector<PassFrame>& window_mean,
                              ReuseCoefficients previous = {});

// Predicts the power of every configuration for the counts of one frame.
class ConfigurationPredictor {
public:
    ConfigurationPredictor(const ConfigurationSpace& space, const PowerModel& fitted,
                           const Configuration& fitted_configuration, ReuseCoefficients reuse);

    PassCoefficients coefficients(std::size_t pass, int level) const;

    // Per-pass, per-level loads for a frame. Counts of passes outside the space (say the
    // fixed-function pass) add the same load to every configuration.
    void set_frame(const std::vector<PassFrame>& frame);

    double predict(const Configuration& configuration) const;
    // out[space.index_of(c)] = predicted power of c.
    void predict_all(std::vector<double>& out) const;

private:
    // q = prod(1 + expm1(-alpha)) - 1 (starting from q0) and, if wanted, e = prod exp(-alpha)
    // for every combination of levels of passes [first, last), in row-major order.
    void enumerate(std::size_t first, std::size_t last, double q0, std::vector<double>& q,
                   std::vector<double>* e) const;

    ConfigurationSpace space_;
    PowerModel fitted_;
    std::vector<std::vector<PassCoefficients>> coefficients_;  // [pass][level]
    std::vector<std::vector<double>> alpha_;                   // [pass][level] for the frame
    std::vector<std::vector<double>> decay_;                   // exp(-alpha)
    std::vector<std::vector<double>> decay_minus_one_;         // expm1(-alpha)
    double alpha_outside_space_ = 0.0;
};

}  // namespace glbudget::model
