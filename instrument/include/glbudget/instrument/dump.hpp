// GLBUDGET_DUMP=DIR writer: what each shader and program costs, for users and for the
// variant manifest. Layout of DIR:
//   index.json                        every program: its hash and its shaders' stages/hashes
//   program-<hash>.json               per stage: static figures and measured averages
//   shader-<hash>.<stage>.glsl        the app's source (strings concatenated)
//   shader-<hash>.<stage>.instrumented.glsl   (when instrumentation succeeded)
//   shader-<hash>.<stage>.json        static figures, or why instrumentation failed
// Files are written to a temporary name and renamed, so a reader never sees half a file;
// they are rewritten as measurements accumulate. Hashes are the caller's (the shim's).
#pragma once

#include "glbudget/instrument/instrument.hpp"

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace glbudget::instrument {

struct ShaderDump {
  std::string hash;
  Stage stage = Stage::fragment;
  std::string original_source;
  InstrumentResult instrumentation;
};

struct ProgramStageDump {
  Stage stage = Stage::fragment;
  std::string shader_hash;
  std::optional<StaticFigures> figures;
  std::optional<StageAverages> measured;  // empty until counters were read back
};

struct ProgramDump {
  std::string hash;
  std::vector<ProgramStageDump> stages;
};

// JSON text of each file (stable key order, indented).
std::string shader_json(const ShaderDump& shader);
std::string program_json(const ProgramDump& program);
std::string index_json(const std::vector<ProgramDump>& programs);

// Each returns an empty string on success, else a one-line reason.
std::string write_shader_dump(const std::filesystem::path& dir, const ShaderDump& shader);
std::string write_program_dump(const std::filesystem::path& dir, const ProgramDump& program);
std::string write_index(const std::filesystem::path& dir, const std::vector<ProgramDump>& programs);

}  // namespace glbudget::instrument
