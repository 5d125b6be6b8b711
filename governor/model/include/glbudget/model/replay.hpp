#pragma once
// Replays a frame log through the run-time power model exactly as the governor would run it
// (predict each frame with the coefficients available at that moment, then feed it to the
// online fitter) and through the Vatjus-Anttila baseline (fitted once on the first window),
// and reports both models' errors on the same frames, split into frames rendered in the
// configuration the model was fitted on and frames whose prediction reused the coefficients.
#include <cstddef>
#include <vector>

#include "glbudget/model/frame_log.hpp"
#include "glbudget/model/online_fitter.hpp"
#include "glbudget/model/prediction_error.hpp"
#include "glbudget/model/reuse.hpp"
#include "glbudget/model/variant_table.hpp"

namespace glbudget::model {

struct ReplayReport {
    PredictionError ours_fitted, ours_reused, baseline_fitted, baseline_reused;
    std::size_t frames = 0;
    std::size_t frames_unusable = 0;  // no power or unmeasured counts
    std::size_t fits = 0;
    std::size_t checks_failed = 0;
    ReuseCoefficients reuse;          // after the last fit
};

ReplayReport replay_frames(const std::vector<LoggedFrame>& frames, const PlatformProfile& profile,
                           const VariantTable& variants, const FitSettings& settings = {});

}  // namespace glbudget::model
