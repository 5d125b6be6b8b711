#include "variant_dump.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <string>

#include <nlohmann/json.hpp>

#include "configuration.hpp"
#include "messages.hpp"
#include "options.hpp"
#include "pass_names.hpp"

namespace glbudget {

namespace {

struct Registry {
  std::mutex mu;
  // pass -> level -> programs, by log hash and by dump name
  std::map<int, std::map<size_t, std::set<std::string>>> hashes, programs;
  bool write_failed = false;
};

Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: programs may link during exit
  return *r;
}

nlohmann::ordered_json table_json(const Registry& r) {
  const manifest::Manifest& m = active_manifest();
  nlohmann::ordered_json passes = nlohmann::ordered_json::array();
  for (size_t i = 0; i < m.passes.size(); ++i) {
    const manifest::Pass& pass = m.passes[i];
    nlohmann::ordered_json levels = nlohmann::ordered_json::array();
    const auto drawn = r.hashes.find(static_cast<int>(i));
    const auto dumped = r.programs.find(static_cast<int>(i));
    for (size_t l = 0; l < pass.levels.size(); ++l) {
      const manifest::Level& level = pass.levels[l];
      nlohmann::ordered_json j{{"name", level.name}};
      if (drawn != r.hashes.end())
        if (auto h = drawn->second.find(l); h != drawn->second.end()) j["hashes"] = h->second;
      if (dumped != r.programs.end())
        if (auto h = dumped->second.find(l); h != dumped->second.end()) j["programs"] = h->second;
      if (level.fragment_scale_or_default() != 1.0) j["fragment_scale"] = level.fragment_scale_or_default();
      if (!level.draws) j["draws"] = false;
      levels.push_back(std::move(j));
    }
    nlohmann::ordered_json p{{"name", pass.name}};
    if (!pass.scales.empty()) p["scales"] = pass.scales;
    p["levels"] = std::move(levels);
    passes.push_back(std::move(p));
  }
  // The name the shim looks up the measured table by (the program itself, not a script or
  // symlink that started it).
  return {{"executable", executable_name()}, {"manifest", m.path}, {"passes", std::move(passes)}};
}

void write_table(Registry& r) {
  const std::filesystem::path dir = options().dump_dir;
  const std::filesystem::path temporary = dir / ".variants.json.tmp";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << table_json(r).dump(1) << "\n";
    if (!out.flush()) ec = std::make_error_code(std::errc::io_error);
  }
  if (!ec) std::filesystem::rename(temporary, dir / "variants.json", ec);
  if (ec && !r.write_failed) {
    r.write_failed = true;
    say("cannot write " + (dir / "variants.json").string() + ": " + ec.message());
  }
}

}  // namespace

void dump_pass_programs(int pass, const std::vector<DrawnProgram>& program_at_level) {
  if (options().dump_dir.empty() || pass < 0) return;
  Registry& r = registry();
  std::lock_guard lock(r.mu);
  bool added = false;
  for (size_t l = 0; l < program_at_level.size(); ++l)
    added |= r.hashes[pass][l].insert(hash_text(program_at_level[l].log_hash)).second |
             r.programs[pass][l].insert(program_at_level[l].dump_name).second;
  if (added) write_table(r);
}

}  // namespace glbudget
