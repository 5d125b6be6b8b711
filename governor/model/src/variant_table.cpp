#include "glbudget/model/variant_table.hpp"

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace glbudget::model {
namespace {

using nlohmann::json;

double cost_field(const json& level, const char* key, const std::string& where) {
    const auto it = level.find(key);
    if (it == level.end()) return 0.0;  // e.g. no texel accesses
    if (!it->is_number() || !std::isfinite(it->get<double>()) || it->get<double>() < 0.0) {
        std::cerr << "glbudget: " << where << ": \"" << key << "\" must be a number >= 0, using 0\n";
        return 0.0;
    }
    return it->get<double>();
}

}  // namespace

std::optional<VariantTable> parse_variant_table(const std::string& json_text, const std::string& source) {
    const json document = json::parse(json_text, nullptr, /*allow_exceptions=*/false);
    if (!document.is_object() || !document.contains("passes") || !document["passes"].is_array()) {
        std::cerr << "glbudget: " << source << ": expected {\"passes\": [...]}\n";
        return std::nullopt;
    }
    std::vector<PassVariants> passes;
    std::map<std::string, VariantRef> by_hash;
    for (const json& pass : document["passes"]) {
        if (!pass.is_object() || !pass.contains("name") || !pass["name"].is_string() ||
            !pass.contains("levels") || !pass["levels"].is_array() || pass["levels"].empty()) {
            std::cerr << "glbudget: " << source << ": a pass needs a \"name\" and non-empty \"levels\"; skipped\n";
            continue;
        }
        PassVariants variants{pass["name"].get<std::string>(), {}};
        const std::string where = source + ": pass " + variants.pass;
        for (const json& level : pass["levels"]) {
            if (!level.is_object() || !level.contains("hash") || !level["hash"].is_string()) {
                std::cerr << "glbudget: " << where << ": a level needs a \"hash\"; skipped\n";
                continue;
            }
            by_hash[level["hash"].get<std::string>()] = {passes.size(), static_cast<int>(variants.levels.size())};
            variants.levels.push_back({cost_field(level, "ins_v", where), cost_field(level, "ins_f", where),
                                       cost_field(level, "tex_f", where)});
        }
        if (!variants.levels.empty()) passes.push_back(std::move(variants));
    }
    return VariantTable{ConfigurationSpace(std::move(passes)), std::move(by_hash)};
}

std::optional<VariantTable> load_variant_table(const std::string& path) {
    std::ifstream in(path);
    if (!in) {
        std::cerr << "glbudget: cannot read variant table " << path << "\n";
        return std::nullopt;
    }
    std::stringstream text;
    text << in.rdbuf();
    return parse_variant_table(text.str(), path);
}

ResolvedFrame resolve_frame(const LoggedFrame& frame, const VariantTable& table,
                            const Configuration& default_configuration) {
    ResolvedFrame resolved;
    resolved.sample.power_w = frame.power_w;
    resolved.configuration = default_configuration;
    resolved.configuration.resize(table.space.pass_count(), 0);
    for (const LoggedPass& logged : frame.passes) {
        std::string name = logged.pass;
        double texels_per_fragment = 1.0;
        if (const auto it = table.by_hash.find(logged.pass); it != table.by_hash.end()) {
            const PassVariants& pass = table.space.passes()[it->second.pass];
            name = pass.pass;
            resolved.configuration[it->second.pass] = it->second.level;
            texels_per_fragment = pass.levels[static_cast<std::size_t>(it->second.level)].tex_f;
        }
        resolved.totals.triangles += logged.primitives;
        resolved.totals.batches += logged.counts.batches;
        resolved.totals.texels += logged.counts.fragments * texels_per_fragment;
        // Several programs can form one pass: their counts add up.
        bool merged = false;
        for (PassFrame& existing : resolved.sample.passes) {
            if (existing.pass != name) continue;
            existing.counts.batches += logged.counts.batches;
            existing.counts.vertices += logged.counts.vertices;
            existing.counts.fragments += logged.counts.fragments;
            merged = true;
        }
        if (!merged) resolved.sample.passes.push_back({name, logged.counts});
    }
    return resolved;
}

}  // namespace glbudget::model
