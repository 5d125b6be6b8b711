#pragma once
// The per-pass power model of paper eq. (3):
//   P = P_m + (P_M - P_m)(1 - exp(-sum_i alpha_i)),
//   alpha_i = k_bi b_i/B + k_vi v_i/V + k_fi f_i/F.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "glbudget/model/platform_profile.hpp"

namespace glbudget::model {

// What one pass drew in one frame. NaN means "not measured".
struct PassCounts {
  double batches = 0.0;
  double vertices = 0.0;   // vertex-shader invocations
  double fragments = 0.0;  // fragment-shader invocations
};

struct PassCoefficients {
  double k_b = 0.0;
  double k_v = 0.0;
  double k_f = 0.0;
};

// A pass's one identity, from the shim's frame record through every fit: the index of the
// pass in the ConfigurationSpace, and past its passes, a pass outside it (a program no pass
// matched, in a replayed log). PassNames gives the names of both.
using PassIndex = std::uint32_t;

struct PassFrame {
  PassIndex pass = 0;
  PassCounts counts;
};

// One rendering sample (paper §5.3 footnote): measured power and per-pass counts of a frame.
struct FrameSample {
  double power_w = 0.0;
  std::vector<PassFrame> passes;
};

// True when the power and every count are finite and the counts are non-negative.
bool is_usable(const FrameSample& sample);

// Normalised load of one pass.
double pass_alpha(const PlatformProfile& profile, const PassCoefficients& k, const PassCounts& c);

class PowerModel {
 public:
  explicit PowerModel(PlatformProfile profile = {}) : profile_(profile) {}

  const PlatformProfile& profile() const { return profile_; }
  // Passes that were never fitted have no entry and contribute nothing. By PassIndex.
  const std::vector<std::optional<PassCoefficients>>& coefficients() const { return coefficients_; }
  const PassCoefficients* find(PassIndex pass) const {
    return pass < coefficients_.size() && coefficients_[pass] ? &*coefficients_[pass] : nullptr;
  }
  void set(PassIndex pass, const PassCoefficients& k);
  std::size_t fitted_passes() const;

  // Beyond the paper: a load every frame carries whatever it draws (the app's and driver's
  // own work per frame, clears, presentation), which P_m, the idle power, does not include.
  // Without it such a cost is absorbed by whichever pass's draw count never changes, and
  // vanishes from predictions of configurations that skip that pass.
  double frame_alpha() const { return frame_alpha_; }
  void set_frame_alpha(double alpha) { frame_alpha_ = alpha; }

  double alpha(const std::vector<PassFrame>& passes) const;
  double predict_power(const std::vector<PassFrame>& passes) const;

 private:
  PlatformProfile profile_;
  std::vector<std::optional<PassCoefficients>> coefficients_;
  double frame_alpha_ = 0.0;
};

}  // namespace glbudget::model
