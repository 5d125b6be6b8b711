#include "glbudget/analysis/resolved_frame.hpp"

#include <optional>
#include <utility>

namespace glbudget::analysis {

using namespace glbudget::model;

ResolvedFrame resolve_frame(const LoggedFrame& frame, const VariantTable& table,
                            const Configuration& default_configuration, PassNames& names) {
  ResolvedFrame resolved;
  resolved.sample.power_w = frame.power_w;
  resolved.configuration = default_configuration;
  resolved.configuration.resize(table.space.pass_count(), 0);
  // The configuration the frame was drawn in, where the log says (the governor logs what it
  // applied); otherwise the variants the frame drew tell their passes' levels.
  const std::optional<Configuration> logged =
      frame.configuration.empty() ? std::nullopt : parse_configuration(frame.configuration, table.space);
  std::vector<double> texels_per_fragment;
  for (const LoggedPass& logged_pass : frame.passes) {
    PassIndex pass = 0;
    bool in_table = false;
    if (const auto it = table.by_hash.find(logged_pass.pass); it != table.by_hash.end()) {
      pass = static_cast<PassIndex>(it->second.pass);
      if (!logged && it->second.level >= 0) resolved.configuration[it->second.pass] = it->second.level;
      in_table = true;
    } else {
      pass = names.index_of(logged_pass.pass);
    }
    resolved.totals.triangles += logged_pass.primitives;
    resolved.totals.batches += logged_pass.counts.batches;
    // Several programs can form one pass: their counts add up.
    bool merged = false;
    for (std::size_t i = 0; i < resolved.sample.passes.size(); ++i) {
      PassFrame& existing = resolved.sample.passes[i];
      if (existing.pass != pass) continue;
      existing.counts.batches += logged_pass.counts.batches;
      existing.counts.vertices += logged_pass.counts.vertices;
      existing.counts.fragments += logged_pass.counts.fragments;
      resolved.primitives[i] += logged_pass.primitives;
      merged = true;
    }
    if (!merged) {
      resolved.sample.passes.push_back({pass, logged_pass.counts});
      resolved.primitives.push_back(logged_pass.primitives);
      texels_per_fragment.push_back(in_table ? -1.0 : 1.0);  // -1: from the level, below
    }
  }
  if (logged) resolved.configuration = *logged;
  for (std::size_t i = 0; i < resolved.sample.passes.size(); ++i) {
    double tex = texels_per_fragment[i];
    if (tex < 0.0) {
      const VariantCost* level = table.space.level_of(resolved.sample.passes[i].pass, resolved.configuration);
      tex = level ? level->tex_f : 0.0;
    }
    resolved.totals.texels += resolved.sample.passes[i].counts.fragments * tex;
  }
  return resolved;
}

std::vector<ConfiguredSample> configured_samples(std::span<const LoggedFrame> frames, const VariantTable& table,
                                                 PassNames& names) {
  std::vector<ConfiguredSample> samples;
  samples.reserve(frames.size());
  Configuration current(table.space.pass_count(), 0);
  for (const LoggedFrame& frame : frames) {
    ResolvedFrame resolved = resolve_frame(frame, table, current, names);
    current = resolved.configuration;
    samples.push_back({std::move(resolved.sample), std::move(resolved.configuration)});
  }
  return samples;
}

FrameTotals totals_in(const ResolvedFrame& frame, const VariantTable& table, const Configuration& target) {
  FrameTotals totals;
  const ConfigurationSpace& space = table.space;
  for (std::size_t j = 0; j < frame.sample.passes.size(); ++j) {
    const PassFrame& p = frame.sample.passes[j];
    double fragment_ratio = 1.0;
    bool draws = true;
    double tex = 1.0;
    if (const VariantCost* to = space.level_of(p.pass, target)) {
      draws = to->draws, tex = to->tex_f;
      for (std::size_t i : space.scalers_of(p.pass)) {
        const VariantCost& from_scale = *space.level_of(i, frame.configuration);
        const VariantCost& to_scale = *space.level_of(i, target);
        fragment_ratio *= from_scale.fragment_scale > 0.0 ? to_scale.fragment_scale / from_scale.fragment_scale : 0.0;
      }
    }
    if (!draws) continue;
    totals.triangles += frame.primitives[j];
    totals.batches += p.counts.batches;
    totals.texels += p.counts.fragments * fragment_ratio * tex;
  }
  return totals;
}

}  // namespace glbudget::analysis
