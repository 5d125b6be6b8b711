#pragma once
// Run-time fitting of paper §5.3/§5.5: collect a fitting window, fit, then keep checking the
// prediction error over accuracy-check windows and refit when its mean exceeds a threshold.
#include <cstddef>
#include <vector>

#include "glbudget/model/power_model.hpp"
#include "glbudget/model/window_fit.hpp"

namespace glbudget::model {

struct FitSettings {
  std::size_t fitting_window = 30;  // frames per regression
  std::size_t check_window = 10;    // frames per accuracy check
  double refit_threshold = 0.10;    // mean |error| as a share of P_M - P_m that triggers a refit
  // The paper starts fitting whenever a new configuration is set (§6.2); false: the new
  // configuration is checked first and only refitted when the check fails.
  bool refit_on_change = true;
  WindowFitSettings regression;
};

class OnlineFitter {
 public:
  enum class Phase { Fitting, Checking };
  enum class Event { None, Rejected, Fitted, CheckPassed, CheckFailed };

  OnlineFitter(PlatformProfile profile, FitSettings settings = {});

  // Feeds one frame. `predicted_power_w` is what the governor predicted for this frame (from
  // the fitted coefficients, or reused ones after a configuration change); it is only used
  // while checking. Frames with NaN/infinite values are rejected and change nothing.
  Event add_frame(const FrameSample& sample, double predicted_power_w);

  // The rendered configuration changed: samples of the old one must not be mixed into a
  // window's regression, so a partial fitting window is dropped, and a new window starts
  // (or, without refit_on_change, the new configuration is checked first).
  void configuration_changed();

  // Coefficients found elsewhere (a fit over several configurations, history_fit.hpp) become
  // the model that checks and the next window's prior.
  void adopt(const PowerModel& model) { model_ = model; }

  Phase phase() const { return phase_; }
  bool has_model() const { return fits_ > 0; }
  const PowerModel& model() const { return model_; }
  std::size_t fits() const { return fits_; }
  const WindowFitResult& last_fit() const { return last_fit_; }
  // Per-pass mean counts of the last fitting window (weights for reuse, see reuse.hpp).
  const std::vector<PassFrame>& last_window_mean() const { return last_window_mean_; }

 private:
  void fit();

  FitSettings settings_;
  PowerModel model_;
  Phase phase_ = Phase::Fitting;
  std::vector<FrameSample> window_;
  double check_error_sum_ = 0.0;
  std::size_t check_frames_ = 0;
  std::size_t fits_ = 0;
  WindowFitResult last_fit_;
  std::vector<PassFrame> last_window_mean_;
};

}  // namespace glbudget::model
