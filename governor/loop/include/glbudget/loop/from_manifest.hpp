#pragma once
// The model's view of the variant manifest: its configuration space (the variant table) and
// the per-pass errors of its levels. No second format: the manifest is the table.
#include "glbudget/loop/error_table.hpp"
#include "glbudget/manifest/manifest.hpp"
#include <string>
#include <vector>

#include "glbudget/model/configuration_space.hpp"
#include "glbudget/model/variant_table.hpp"

namespace glbudget::loop {

// One PassVariants per manifest pass, in manifest order, named as the pass. A level's cost is
// its fragment_scale_or_default() and draws; instructions and texels per invocation are 0
// until the shader instrumentation measures them (the run-time model works without them).
model::ConfigurationSpace space_from_manifest(const manifest::Manifest& manifest);

// The same space with each level's instructions and texel accesses per invocation taken from
// `costs`, what `glbudget calibrate --app` measured (a variant table whose passes carry the
// manifest's pass names). A pass the table lacks keeps zero costs silently (the built-in
// resolution pass, a pass with no program); a pass listed with another number of levels (the
// manifest changed since) keeps zero costs and adds a line to `problems`.
model::ConfigurationSpace space_from_manifest(const manifest::Manifest& manifest, const model::VariantTable& costs,
                                              std::vector<std::string>& problems);

// e_i(l) from the levels' `error` keys; levels without one get the stand-in
// (ErrorTable::stand_in), which the table remembers.
ErrorTable errors_from_manifest(const manifest::Manifest& manifest);

}  // namespace glbudget::loop
