#include "glbudget/model/replay.hpp"

#include <cmath>
#include <optional>

#include "glbudget/model/vatjus_anttila_model.hpp"

namespace glbudget::model {

ReplayReport replay_frames(const std::vector<LoggedFrame>& frames, const PlatformProfile& profile,
                           const VariantTable& variants, const FitSettings& settings) {
    const double range = profile.range_w();
    ReplayReport report;
    report.ours_fitted = report.ours_reused = PredictionError(range);
    report.baseline_fitted = report.baseline_reused = PredictionError(range);
    OnlineFitter fitter(profile, settings);
    VatjusAnttilaModel baseline(profile);
    std::vector<FrameTotals> baseline_window;
    std::vector<double> baseline_power;

    Configuration current(variants.space.pass_count(), 0);
    Configuration fitted_configuration;
    std::optional<ConfigurationPredictor> predictor;

    for (const LoggedFrame& logged : frames) {
        ++report.frames;
        const ResolvedFrame frame = resolve_frame(logged, variants, current);
        if (!is_usable(frame.sample)) {
            ++report.frames_unusable;
            continue;
        }
        if (frame.configuration != current) {
            current = frame.configuration;
            fitter.configuration_changed();
        }
        const FrameTotals totals = frame.totals;

        double predicted = std::nan("");
        if (predictor) {
            predictor->set_frame(frame.sample.passes);
            predicted = predictor->predict(current);
            const double predicted_baseline = baseline.fitted() ? baseline.predict_power(totals) : std::nan("");
            // Both models are scored on the same frames only.
            if (std::isfinite(predicted) && std::isfinite(predicted_baseline)) {
                const bool fitted_here = current == fitted_configuration;
                (fitted_here ? report.ours_fitted : report.ours_reused).add(predicted, frame.sample.power_w);
                (fitted_here ? report.baseline_fitted : report.baseline_reused)
                    .add(predicted_baseline, frame.sample.power_w);
            }
        }

        if (!baseline.fitted() && std::isfinite(totals.triangles) && std::isfinite(totals.texels)) {
            baseline_window.push_back(totals);
            baseline_power.push_back(frame.sample.power_w);
            if (baseline_window.size() >= settings.fitting_window) baseline.fit(baseline_window, baseline_power);
        }

        const OnlineFitter::Event event = fitter.add_frame(frame.sample, predicted);
        if (event == OnlineFitter::Event::CheckFailed) ++report.checks_failed;
        if (event == OnlineFitter::Event::Fitted) {
            ++report.fits;
            fitted_configuration = current;
            report.reuse = solve_reuse(fitter.model(), variants.space, fitted_configuration,
                                       fitter.last_window_mean(), report.reuse);
            predictor.emplace(variants.space, fitter.model(), fitted_configuration, report.reuse);
        }
    }
    return report;
}

}  // namespace glbudget::model
