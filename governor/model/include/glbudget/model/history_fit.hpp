#pragma once
// Beyond the paper: one regression over the recent frames of *several* configurations.
//
// The paper fits per-pass k_b, k_v, k_f on a window of one configuration and reuses them for
// the others through chi and psi, solved from that one configuration (§5.4). Within one
// configuration a pass's counts often barely change (a slow camera), so the window cannot
// tell a pass's per-fragment cost from its per-draw or fixed cost, and what it guesses is
// extrapolated to every other configuration. Frames drawn in different configurations tell
// these apart: the render scale moves fragments but not draws, shader levels move
// instructions and texels per fragment. So once the history holds more than one
// configuration, every pass's level-independent costs and the shared chi and psi are fitted
// together, with the paper's parameterisation:
//   k_bi = b_i,   k_vi(l) = c_i + chi dIns_vi(l),   k_fi(l) = a_i + chi dIns_fi(l) + psi dTex_fi(l),
// where d is the level's excess over the pass's cheapest level (so every cost stays >= 0 when
// the unknowns are >= 0), plus the per-frame load of power_model.hpp. Rows are weighted and columns scaled as in the
// window fit; a ridge towards the previous model holds what the history cannot identify.
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/configured_sample.hpp"
#include "glbudget/model/power_model.hpp"
#include "glbudget/model/reuse.hpp"

namespace glbudget::model {

struct HistoryFitSettings {
  // Ridge strength relative to the scaled columns (see window_fit.hpp).
  double ridge = 1e-3;
  // The same when the profile has calibrated costs (platform_profile.hpp): the prior the
  // model started from is then worth more than a guess. Measured on both recordings of the
  // demo's four scenes, costs from the other scenes: mean 30-frame error 3.5 % at 1e-3,
  // 3.3 % at 3e-3, 2.8 % at 1e-2, 2.9 % at 3e-2 and 1e-1 (README).
  double calibrated_ridge = 1e-2;
  // For the per-frame load: 0 leaves it free, so constant costs go there first.
  double frame_ridge = 0.0;
};

struct HistoryFit {
  PowerModel model;             // k of every pass at the levels of `configuration`
  Configuration configuration;  // as asked for by `express_at`
  ReuseCoefficients reuse;      // chi, psi
  std::size_t samples_used = 0;
  std::size_t configurations = 0;  // distinct configurations among them
  std::size_t columns = 0;
};

// nullopt when no usable sample lies in the space. `prior` (k at `prior_configuration`) and
// `prior_reuse` are what the ridge pulls towards.
std::optional<HistoryFit> fit_history(std::span<const ConfiguredSample> samples, const ConfigurationSpace& space,
                                      const PowerModel& prior, const Configuration& prior_configuration,
                                      ReuseCoefficients prior_reuse, const Configuration& express_at,
                                      const HistoryFitSettings& settings = {});

}  // namespace glbudget::model
