#pragma once
// Beyond the paper (issue 14): the render scale does not add to the other passes' errors as
// §6.2's sum takes it. A probe frame draws the best configuration beside the one shown, so it
// measures the shown configuration's true error, combination included. ScaleFactors fits, per
// level l of the render-scale pass, the factor m(l) in
//   e(s) = e_scale(l) + m(l) * sum over the other passes of e_i(l_i)
// by least squares over the probes of configurations shown at that level (their sums faded
// over memory_probes), shrunk toward 1 (the sum) by prior_probes and held in [0.5, 1.5].
// Replayed on two rounds of the error estimates, the demo's Hall ranked at 0.967-0.968 against
// 0.951 with the sum, the other scenes within -0.003 and +0.007
// (docs/evaluation/probes/probe-sweeps.md, "a render-scale factor fitted from the configurations
// shown"). Off by default: GLBUDGET_SCALE_FACTORS=1.

#include <cstddef>
#include <vector>

namespace glbudget::loop {

class ScaleFactors {
 public:
  explicit ScaleFactors(double memory_probes = 16.0, double prior_probes = 4.0);

  // A probe measured `measured` for a configuration shown at `scale_level`, whose scale pass
  // alone errs by `scale_error` and whose other passes' errors sum to `others_error`. Ignored
  // at level 0 (no factor there), where the others sum to 0, and for values that are not
  // finite or are negative.
  void add(int scale_level, double scale_error, double others_error, double measured);

  // m(l) for l in [0, levels): 1 at level 0 and at levels no probe measured.
  std::vector<double> factors(std::size_t levels) const;
  std::size_t probes() const { return probes_; }

 private:
  struct Sums {
    double product = 0.0, square = 0.0, weight = 0.0;  // faded sums of (measured - scale) * others, others^2, 1
  };
  double memory_probes_, prior_probes_;
  std::vector<Sums> levels_;
  std::size_t probes_ = 0;
};

}  // namespace glbudget::loop
