#include "glbudget/model/run_time_model.hpp"

#include <cmath>
#include <limits>

namespace glbudget::model {

RunTimeModel::RunTimeModel(PlatformProfile profile, ConfigurationSpace space, FitSettings fit,
                           HistorySettings history)
    : space_(std::move(space)), history_settings_(history), fitter_(profile, fit) {}

double RunTimeModel::predict_frame(const FrameSample& frame, const Configuration& configuration) {
    if (!current_.empty() && configuration != current_) fitter_.configuration_changed();
    current_ = configuration;
    if (!predictor_) return std::numeric_limits<double>::quiet_NaN();
    predictor_->set_frame(frame.passes, configuration);
    return predictor_->predict(configuration);
}

double RunTimeModel::predict(const Configuration& configuration) const {
    if (!predictor_ || !space_.contains(configuration)) return std::numeric_limits<double>::quiet_NaN();
    return predictor_->predict(configuration);
}

void RunTimeModel::predict_all(std::vector<double>& out) const {
    if (predictor_) predictor_->predict_all(out);
    else out.assign(space_.size(), std::numeric_limits<double>::quiet_NaN());
}

OnlineFitter::Event RunTimeModel::learn(const FrameSample& frame, const Configuration& configuration,
                                        double predicted_w) {
    if (is_usable(frame) && space_.contains(configuration)) {
        history_.push_back({frame, configuration});
        while (history_.size() > history_settings_.frames) history_.pop_front();
    }
    const OnlineFitter::Event event = fitter_.add_frame(frame, predicted_w);
    if (event != OnlineFitter::Event::Fitted) return event;

    // The paper: the window's coefficients, chi and psi from them.
    PowerModel model = fitter_.model();
    Configuration fitted_at = configuration;
    reuse_ = solve_reuse(model, space_, configuration, fitter_.last_window_mean(), reuse_);
    fitted_configurations_ = {configuration};
    // Beyond it: with several configurations in the history, one fit over all of them.
    if (history_settings_.enabled) {
        std::set<Configuration> seen;
        for (const ConfiguredSample& s : history_) seen.insert(s.configuration);
        if (seen.size() > 1) {
            const std::vector<ConfiguredSample> samples(history_.begin(), history_.end());
            if (auto fit = fit_history(samples, space_, model, configuration, reuse_, configuration,
                                       history_settings_.fit)) {
                model = fit->model;
                reuse_ = fit->reuse;
                fitted_configurations_ = seen;
                fitter_.adopt(model);
                ++history_fits_;
            }
        }
    }
    fitted_configuration_ = fitted_at;
    if (predictor_) predictor_->refit(model, fitted_at, reuse_);
    else predictor_.emplace(space_, model, fitted_at, reuse_);
    return event;
}

}  // namespace glbudget::model
