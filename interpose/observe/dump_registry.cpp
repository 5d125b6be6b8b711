#include "dump_registry.hpp"

#include <unistd.h>

#include <map>
#include <mutex>
#include <set>

#include "options.hpp"

namespace glbudget::dump_registry {

namespace {
using instrument::CounterWords;
using instrument::ProgramDump;
using instrument::StageCounts;

struct Registry {
  std::mutex mu;
  std::map<std::string, ProgramDump> programs;                       // by hash
  std::map<std::string, std::map<uint64_t, CounterWords>> counters;  // program -> source -> words
  std::set<std::string> changed;                                     // programs to rewrite
  bool write_failed = false;                                         // said once
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: the exit flush uses it
  return *r;
}

const std::string& dump_dir() { return options().dump_dir; }

void report_write(Registry& r, const std::string& error) {
  if (error.empty() || r.write_failed) return;
  r.write_failed = true;  // one line, not one per file
  std::string line = "glbudget: GLBUDGET_DUMP: " + error + "\n";
  (void)!write(STDERR_FILENO, line.data(), line.size());
}

std::optional<instrument::StageAverages> measured_locked(Registry& r, const std::string& hash,
                                                         instrument::Stage stage) {
  auto it = r.counters.find(hash);
  if (it == r.counters.end() || it->second.empty()) return std::nullopt;
  StageCounts total;
  for (const auto& [source, words] : it->second) total = total + instrument::read_stage_counts(words, stage);
  return instrument::averages(total);
}

void write_program_locked(Registry& r, ProgramDump program) {
  for (auto& stage : program.stages) stage.measured = measured_locked(r, program.hash, stage.stage);
  report_write(r, instrument::write_program_dump(dump_dir(), program));
}
}  // namespace

void add_shader(const instrument::ShaderDump& shader) {
  if (dump_dir().empty()) return;
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  report_write(r, instrument::write_shader_dump(dump_dir(), shader));
}

void add_program(const ProgramDump& program) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  r.programs[program.hash] = program;
  if (dump_dir().empty()) return;
  write_program_locked(r, program);
  std::vector<ProgramDump> all;
  for (const auto& [hash, p] : r.programs) all.push_back(p);
  report_write(r, instrument::write_index(dump_dir(), all));
}

void set_counters(const std::string& program_hash, uint64_t source, const CounterWords& words) {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  CounterWords& slot = r.counters[program_hash][source];
  if (slot != words) r.changed.insert(program_hash);
  slot = words;
}

void write_changed() {
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  if (!dump_dir().empty())
    for (const std::string& hash : r.changed) {
      auto it = r.programs.find(hash);
      if (it != r.programs.end()) write_program_locked(r, it->second);
    }
  r.changed.clear();
}

}  // namespace glbudget::dump_registry
