#include "glbudget/loop/from_manifest.hpp"

#include <algorithm>

namespace glbudget::loop {

model::ConfigurationSpace space_from_manifest(const manifest::Manifest& manifest) {
  std::vector<model::PassVariants> passes;
  passes.reserve(manifest.passes.size());
  for (const manifest::Pass& pass : manifest.passes) {
    model::PassVariants variants{pass.name, {}, pass.scales};
    for (const manifest::Level& level : pass.levels) {
      model::VariantCost cost;
      cost.fragment_scale = level.fragment_scale_or_default();
      cost.draws = level.draws;
      variants.levels.push_back(cost);
    }
    passes.push_back(std::move(variants));
  }
  return model::ConfigurationSpace(std::move(passes));
}

model::ConfigurationSpace space_from_manifest(const manifest::Manifest& manifest, const model::VariantTable& costs,
                                              std::vector<std::string>& problems) {
  std::vector<model::PassVariants> passes = space_from_manifest(manifest).passes();
  for (model::PassVariants& pass : passes) {
    const auto measured = std::find_if(costs.space.passes().begin(), costs.space.passes().end(),
                                       [&](const model::PassVariants& p) { return p.pass == pass.pass; });
    if (measured == costs.space.passes().end()) continue;
    if (measured->levels.size() != pass.levels.size()) {
      problems.push_back("pass '" + pass.pass + "' has " + std::to_string(pass.levels.size()) +
                         " levels in the manifest and " + std::to_string(measured->levels.size()) +
                         " in the measured costs (the manifest changed since `glbudget calibrate --app`); "
                         "its levels' costs are unknown");
      continue;
    }
    for (std::size_t l = 0; l < pass.levels.size(); ++l) {
      pass.levels[l].ins_v = measured->levels[l].ins_v;
      pass.levels[l].ins_f = measured->levels[l].ins_f;
      pass.levels[l].tex_f = measured->levels[l].tex_f;
    }
  }
  return model::ConfigurationSpace(std::move(passes));
}

ErrorTable errors_from_manifest(const manifest::Manifest& manifest) {
  ErrorTable table(space_from_manifest(manifest));
  for (std::size_t i = 0; i < manifest.passes.size(); ++i) {
    const std::vector<manifest::Level>& levels = manifest.passes[i].levels;
    for (std::size_t l = 1; l < levels.size(); ++l) {
      if (levels[l].error) table.set(i, static_cast<int>(l), *levels[l].error);
    }
  }
  return table;
}

}  // namespace glbudget::loop
