#include "glbudget/instrument/dump.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <system_error>

namespace glbudget::instrument {

namespace {

using nlohmann::ordered_json;

ordered_json figures_json(const std::optional<StaticFigures>& f) {
  if (!f) return nullptr;
  return {{"blocks", f->blocks}, {"instructions", f->instructions}, {"texture_calls", f->texture_calls}};
}

ordered_json optional_number(const std::optional<double>& v) { return v ? ordered_json(*v) : ordered_json(nullptr); }

ordered_json measured_json(const std::optional<StageAverages>& m) {
  if (!m) return nullptr;
  return {{"invocations", m->invocations},
          {"instructions_per_invocation", optional_number(m->instructions_per_invocation)},
          {"texel_accesses_per_invocation", optional_number(m->texel_accesses_per_invocation)}};
}

std::string shader_stem(const std::string& hash, Stage stage) { return "shader-" + hash + "." + stage_name(stage); }

// Writes `text` to dir/name through a temporary file and a rename.
std::string write_file(const std::filesystem::path& dir, const std::string& name, const std::string& text) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return "cannot create " + dir.string() + ": " + ec.message();
  const std::filesystem::path target = dir / name;
  const std::filesystem::path temporary = dir / ("." + name + ".tmp");
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << text;
    if (!out.flush()) return "cannot write " + temporary.string();
  }
  std::filesystem::rename(temporary, target, ec);
  if (ec) return "cannot rename " + temporary.string() + ": " + ec.message();
  return {};
}

}  // namespace

std::string shader_json(const ShaderDump& shader) {
  const InstrumentResult& r = shader.instrumentation;
  ordered_json j{{"hash", shader.hash},
                 {"stage", stage_name(shader.stage)},
                 {"instrumented", r.ok},
                 {"static", figures_json(r.figures)}};
  if (!r.ok) j["error"] = r.error;
  return j.dump(2) + "\n";
}

std::string program_json(const ProgramDump& program) {
  ordered_json stages = ordered_json::array();
  for (const ProgramStageDump& s : program.stages)
    stages.push_back({{"stage", stage_name(s.stage)},
                      {"shader", s.shader_hash},
                      {"static", figures_json(s.figures)},
                      {"measured", measured_json(s.measured)}});
  return ordered_json{{"hash", program.hash}, {"stages", stages}}.dump(2) + "\n";
}

std::string index_json(const std::vector<ProgramDump>& programs) {
  ordered_json list = ordered_json::array();
  for (const ProgramDump& p : programs) {
    ordered_json shaders = ordered_json::array();
    for (const ProgramStageDump& s : p.stages)
      shaders.push_back({{"stage", stage_name(s.stage)}, {"hash", s.shader_hash}});
    list.push_back({{"hash", p.hash}, {"file", "program-" + p.hash + ".json"}, {"shaders", shaders}});
  }
  return ordered_json{{"programs", list}}.dump(2) + "\n";
}

std::string write_shader_dump(const std::filesystem::path& dir, const ShaderDump& shader) {
  const std::string stem = shader_stem(shader.hash, shader.stage);
  if (std::string e = write_file(dir, stem + ".glsl", shader.original_source); !e.empty()) return e;
  if (shader.instrumentation.ok) {
    if (std::string e = write_file(dir, stem + ".instrumented.glsl", shader.instrumentation.instrumented_source);
        !e.empty())
      return e;
  }
  return write_file(dir, stem + ".json", shader_json(shader));
}

std::string write_program_dump(const std::filesystem::path& dir, const ProgramDump& program) {
  return write_file(dir, "program-" + program.hash + ".json", program_json(program));
}

std::string write_index(const std::filesystem::path& dir, const std::vector<ProgramDump>& programs) {
  return write_file(dir, "index.json", index_json(programs));
}

}  // namespace glbudget::instrument
