#pragma once
// Beyond the paper: a selection under a power budget ranks configurations never measured at a
// high quantile of what first windows drew over their predictions (PowerFeedback's guard:
// z times the typical surprise). Where that leaves nothing within the margin under the budget,
// the selection falls back to what comes closest to keeping it, and at that quantile a
// measured configuration whose windows go over the budget outranks every cheaper one never
// tried: the run stays over the budget until the surprise fades. On the demo's Valley at 40 %
// (run P, 2026-11-29) a first configuration predicted at 11.8 W drew 15.2 W; the run held it
// for 28 s, 21 of those windows over the budget, while one predicted 2.8 W cheaper and never
// measured stood 0.6 W dearer under the guard. There the selection is made again with every
// unmeasured configuration at its expected power, its prediction plus the typical surprise.
#include <span>
#include <vector>

#include "glbudget/model/selection.hpp"

namespace glbudget::loop {

// `guarded_w`: each configuration's power as the selection weighed it, the unmeasured ones
// raised by the guard; `measured`: whether each was measured (and so not raised); `lowered_w`:
// the guard less the typical surprise. Returns `guarded` (the selection made on guarded_w)
// where some configuration fits budget_w - margin_w under guarded_w, where it chose one never
// measured, or where there is no finite margin or nothing to lower (or the sizes disagree);
// else the selection on guarded_w with the unmeasured ones lowered by lowered_w.
model::Selection select_at_expected_power(const model::Selection& guarded, std::span<const double> guarded_w,
                                          const std::vector<bool>& measured, std::span<const double> error,
                                          double budget_w, double margin_w, double lowered_w);

}  // namespace glbudget::loop
