// GLBUDGET_DUMP's variants.json: which programs draw each level of each manifest pass, named
// by the program hashes of the frame log and of the dump's program files, in the variant-table
// format of governor/model/variant_table.hpp (without costs). `glbudget calibrate --app` joins
// it to the dump's measured instructions and texel accesses to get each level's costs.
#pragma once
#include <string>
#include <vector>

#include "frame_row.hpp"

namespace glbudget {

// A linked program of manifest pass `pass`: the program drawn at each of its levels (the app's
// own where a level builds no variant), by its name in the log and in the dump (they differ
// for a variant that only holds uniforms). Rewrites variants.json when it adds something.
struct DrawnProgram {
  PassId log_hash = 0;
  std::string dump_name;
};
void dump_pass_programs(int pass, const std::vector<DrawnProgram>& program_at_level);

}  // namespace glbudget
