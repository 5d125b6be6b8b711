#include "glbudget/loop/from_manifest.hpp"

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
