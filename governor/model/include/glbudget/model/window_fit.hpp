#pragma once
// One regression of paper §5.3: fit every pass's k_b, k_v, k_f to a window of samples.
//
// The regression runs on the linearised model alpha = -ln(1 - (P - P_m)/(P_M - P_m)), which
// is linear in the k. Beyond the paper it is made safe for whatever a window contains:
//  - rows are weighted by exp(-alpha) so residuals match power residuals and samples at or
//    above P_M (clamped, see power_curve.hpp) carry almost no weight;
//  - only (pass, term) pairs with a non-zero count in the window get a column: a pass that
//    drew nothing keeps its previous coefficients and does not disturb the others;
//  - columns are scaled to unit norm, so counts from 0 to 2^40 and beyond condition alike;
//  - a ridge pulls the solution towards a prior: the previous coefficients, or for a pass seen
//    for the first time a pooled fit shared by all passes. Directions the window cannot
//    identify (constant or collinear counts, fewer samples than unknowns) keep their last good
//    value, identifiable ones are fitted to the data. The ridge strength is chosen per window
//    by generalised cross-validation, so noisy windows do not amplify noise into coefficients
//    while noiseless ones are fitted exactly;
//  - all coefficients are costs and are constrained to be non-negative.
#include <cstddef>
#include <span>

#include "glbudget/model/power_model.hpp"

namespace glbudget::model {

struct WindowFitSettings {
  // Ridge strength relative to the scaled columns: directions whose singular value is below
  // about ridge * sqrt(columns) are held at the previous coefficients.
  double ridge = 1e-5;
  // A term counts as "held" when more than this share of its estimate comes from the
  // previous value rather than from the window (reporting only).
  double held_share = 0.1;
};

struct WindowFitResult {
  PowerModel model;
  std::size_t samples_used = 0;
  std::size_t samples_rejected = 0;  // NaN/infinite power or counts
  std::size_t columns = 0;           // (pass, term) pairs the window could speak about
  std::size_t held_terms = 0;        // of those, how many the window could not identify
};

WindowFitResult fit_window(std::span<const FrameSample> window, const PowerModel& previous,
                           const WindowFitSettings& settings = {});

}  // namespace glbudget::model
