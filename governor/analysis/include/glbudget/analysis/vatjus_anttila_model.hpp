#pragma once
// Baseline: the model of Vatjus-Anttila, Koskela & Hickey (NGMAST 2013), as the paper compares
// against it. Power follows the same saturating curve, but its load is one weighted sum of the
// frame's triangles, batches and texels: no per-pass terms, no fragment-shader invocations,
// and the weights are fitted once (on the first window) and never refitted at run time.
// Their fixed correction factor for culled primitives is a constant scale on the triangle
// weight and is absorbed by the fit.
#include <span>

#include "glbudget/model/power_model.hpp"

namespace glbudget::analysis {

struct FrameTotals {
  double triangles = 0.0;
  double batches = 0.0;
  double texels = 0.0;
};

class VatjusAnttilaModel {
 public:
  explicit VatjusAnttilaModel(model::PlatformProfile profile);

  // Fits the three weights (non-negative) to frames with measured power.
  void fit(std::span<const FrameTotals> frames, std::span<const double> power_w);
  bool fitted() const { return fitted_; }
  double predict_power(const FrameTotals& frame) const;

 private:
  // The weighted sum is a one-pass model::PowerModel whose "batches, vertices, fragments" are the
  // frame's batches, triangles and texels, normalised by B, V and F of the profile.
  static std::vector<model::PassFrame> as_single_pass(const FrameTotals& frame);
  model::PowerModel model_;
  bool fitted_ = false;
};

}  // namespace glbudget::analysis
