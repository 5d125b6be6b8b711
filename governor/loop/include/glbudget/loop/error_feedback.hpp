#pragma once
// Beyond the paper: measured quality closes the loop for an error budget as measured power does
// for a power budget. A probe frame draws the best configuration s0 beside the one shown, so
// the probe measures the true error of the configuration drawn, not only those of the probe
// configurations. The additive estimate (§6.2) misjudges it where the passes' errors do not
// add up, and where the passes' errors, probed in turn, are stale: on the demo's Subway, whose
// soldiers move, 0.38-0.47 of the frames shown under an error budget were over it.
// ErrorFeedback keeps, for each configuration shown at a probe frame, the ratio of its measured
// error to its estimate at that frame (a mean of logs over its last memory_probes probes), and
// over every such probe a common ratio for the configurations never shown. A selection under an
// error budget multiplies each estimate by its ratio and by exp(z * spread), z the normal
// quantile of keep_share and the spread that of the logged ratios about the ratio each was
// predicted by, so that about keep_share of the probed frames stay within the budget.
//
// Ratios, not differences: the errors of every configuration grow and shrink together along
// a camera path, and a pass's share of the whole error is what the estimate gets wrong. The
// logs are of (error + floor), floor about SSIM's noise between frames of a still scene, so
// that a configuration whose estimate and measurement are both near 0 has ratio 1.
#include <cstddef>
#include <map>
#include <vector>

#include "glbudget/model/configuration_space.hpp"

namespace glbudget::loop {

struct ErrorFeedbackSettings {
  bool enabled = true;  // GLBUDGET_ERROR_FEEDBACK=0: the estimate as the paper makes it
  double keep_share = 0.95;
  double memory_probes = 4.0;  // a ratio averages its last this-many probes (exponentially)
  double floor = 0.002;        // added to both errors before their ratio is taken
};

class ErrorFeedback {
 public:
  explicit ErrorFeedback(ErrorFeedbackSettings settings = {});

  // A probe frame measured `measured` (1 - SSIM against s0's image of the frame) for the
  // configuration shown, estimated at `estimated` by the table as that probe left it.
  // Ignored when either is not finite or negative, and for the best configuration (its error
  // is 0 by definition).
  void add(const model::Configuration& shown, double estimated, double measured);

  // The estimate corrected: (estimate + floor) * ratio * exp(z * spread) - floor, never below
  // 0; the estimate itself before any probe of a configuration other than the best, for the
  // best configuration and when disabled.
  double correct(const model::Configuration& configuration, double estimated) const;
  // correct() for every configuration of the space (by index), in place.
  void correct_all(const model::ConfigurationSpace& space, std::vector<double>& error) const;

  // log of the ratio applied to a configuration (its own if shown at a probe, else the common one).
  double log_ratio(const model::Configuration& configuration) const;
  double spread() const;  // of the log ratios about the ratio each was predicted by; 0 before a second probe
  std::size_t probes() const { return probes_; }
  const ErrorFeedbackSettings& settings() const { return settings_; }

 private:
  struct Ratio {
    double log = 0.0;
    std::size_t probes = 0;
  };
  ErrorFeedbackSettings settings_;
  double z_ = 0.0;
  std::map<model::Configuration, Ratio> ratios_;
  Ratio common_;
  double deviation_sq_ = 0.0;
  std::size_t deviations_ = 0;
  std::size_t probes_ = 0;
};

}  // namespace glbudget::loop
