#pragma once
// A recorded frame log's frames as the model sees them, through an app's variant table: each
// frame's passes by PassIndex, the configuration it was drawn in, and the totals the
// Vatjus-Anttila baseline takes. For replay, cost fitting and `glbudget calibrate --app`.
#include <span>
#include <vector>

#include "glbudget/analysis/frame_log.hpp"
#include "glbudget/analysis/vatjus_anttila_model.hpp"
#include "glbudget/model/configured_sample.hpp"
#include "glbudget/model/pass_names.hpp"
#include "glbudget/model/variant_table.hpp"

namespace glbudget::analysis {

// A logged frame as the model sees it. Variants listed in the table become their pass's index
// in the space and set that pass's level; other hashes are passes of their own outside the
// search space, indexed by `names` (made from the table's space).
// Passes of the space that drew nothing keep `default_configuration`'s level.
struct ResolvedFrame {
  model::FrameSample sample;
  model::Configuration configuration;
  // For the baseline; texels are fragments x texel accesses per fragment where the table
  // knows the variant, else fragments.
  FrameTotals totals;
  std::vector<double> primitives;  // per entry of sample.passes
};
// The configuration comes from the log's `configuration` column when it has one.
ResolvedFrame resolve_frame(const LoggedFrame& frame, const model::VariantTable& table,
                            const model::Configuration& default_configuration, model::PassNames& names);

// A log's frames as the model sees them, each in the configuration it was drawn in (a frame
// without a configuration column keeps the one before; the first, every pass at level 0).
std::vector<model::ConfiguredSample> configured_samples(std::span<const LoggedFrame> frames,
                                                        const model::VariantTable& table, model::PassNames& names);

// The baseline's totals for the frame's counts drawn in `target` instead: fragments follow the
// levels' scales, texels the target levels' texel accesses, skipped passes drop out.
FrameTotals totals_in(const ResolvedFrame& frame, const model::VariantTable& table, const model::Configuration& target);

}  // namespace glbudget::analysis
