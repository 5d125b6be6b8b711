#include "glbudget/analysis/vatjus_anttila_model.hpp"

#include <algorithm>
#include <vector>

#include "glbudget/model/window_fit.hpp"

namespace glbudget::analysis {

using namespace glbudget::model;

VatjusAnttilaModel::VatjusAnttilaModel(PlatformProfile profile) : model_(profile) {}

std::vector<PassFrame> VatjusAnttilaModel::as_single_pass(const FrameTotals& frame) {
  return {{0, {frame.batches, frame.triangles, frame.texels}}};  // one pass: the whole frame
}

void VatjusAnttilaModel::fit(std::span<const FrameTotals> frames, std::span<const double> power_w) {
  std::vector<FrameSample> samples;
  const std::size_t n = std::min(frames.size(), power_w.size());
  for (std::size_t i = 0; i < n; ++i) samples.push_back({power_w[i], as_single_pass(frames[i])});
  model_ = fit_window(samples, model_).model;
  fitted_ = true;
}

double VatjusAnttilaModel::predict_power(const FrameTotals& frame) const {
  return model_.predict_power(as_single_pass(frame));
}

}  // namespace glbudget::analysis
