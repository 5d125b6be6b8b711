// What instrumentation learnt, process-wide: every shader's static figures, every program's
// stages, and the counters read back for it (from any context). With GLBUDGET_DUMP=DIR the
// files of instrument/dump.hpp are (re)written as this grows.
#pragma once
#include <cstdint>
#include <optional>
#include <string>

#include "glbudget/instrument/dump.hpp"

namespace glbudget {

namespace dump_registry {

void add_shader(const instrument::ShaderDump& shader);
void add_program(const instrument::ProgramDump& program);
// The cumulative counters of one counter buffer (`source`: unique per buffer) that served
// the program named `program_hash`. A later readback of the same buffer replaces an earlier one.
void set_counters(const std::string& program_hash, uint64_t source, const instrument::CounterWords& words);
// Rewrites the program files whose measurements changed since they were last written.
void write_changed();

}  // namespace dump_registry

}  // namespace glbudget
