#include <algorithm>
#include <set>

#include "parsed.hpp"
#include "values.hpp"

namespace glbudget::manifest::detail {
namespace {

// Drops the "pass:NAME" targets of `pass` that name none of `names`, then its levels left
// with nothing to scale. False when that drops level 0, so the pass itself goes.
bool drop_dangling_targets(Reader& reader, ParsedPass& pass, const std::set<std::string>& names) {
  for (std::size_t i = 0; i < pass.levels.size();) {
    ParsedLevel& level = pass.levels[i];
    std::vector<Target>& targets = level.level.targets;
    const bool scaled = !targets.empty();
    for (std::size_t t = 0; t < targets.size();) {
      if (targets[t].kind == Target::Kind::pass && !names.contains(targets[t].name)) {
        reader.report_at(level.target_at[t], level.label + ": target '" + target_text(targets[t]) +
                                                 "' names no pass of the manifest (ignored)");
        targets.erase(targets.begin() + static_cast<std::ptrdiff_t>(t));
        level.target_at.erase(level.target_at.begin() + static_cast<std::ptrdiff_t>(t));
      } else {
        ++t;
      }
    }
    if (!scaled || !targets.empty()) {
      ++i;
      continue;
    }
    // Level 0 never moves: when it is invalid, the pass is dropped before it gets here.
    reader.report_at(level.at,
                     level.label + ": no target left to scale" + (i == 0 ? "; pass dropped" : "; level dropped"));
    if (i == 0) return false;
    pass.levels.erase(pass.levels.begin() + static_cast<std::ptrdiff_t>(i));
  }
  return true;
}

struct PassName {
  std::string name;
  bool has_match = false;
};

// The passes whose fragments the levels' targets scale, in manifest order.
std::vector<std::string> derived_scales(const ParsedPass& pass, const std::vector<PassName>& order) {
  std::set<std::string> scaled;
  for (const ParsedLevel& level : pass.levels) {
    for (const Target& target : level.level.targets) {
      if (target.kind == Target::Kind::self) scaled.insert(pass.pass.name);
      if (target.kind == Target::Kind::pass) scaled.insert(target.name);
      if (target.kind == Target::Kind::default_framebuffer || target.kind == Target::Kind::window_sized) {
        for (const PassName& other : order) {
          if (other.has_match) scaled.insert(other.name);
        }
      }
    }
  }
  std::vector<std::string> scales;
  for (const PassName& other : order) {
    if (scaled.contains(other.name)) scales.push_back(other.name);
  }
  return scales;
}

std::vector<std::string> written_scales(Reader& reader, const ParsedPass& pass, const std::set<std::string>& names) {
  std::vector<std::string> scales;
  for (const auto& [name, at] : *pass.scales) {
    if (!names.contains(name)) {
      reader.report_at(
          at, "pass '" + pass.pass.name + "': '" + name + "' in scales names no pass of the manifest (ignored)");
    } else if (std::find(scales.begin(), scales.end(), name) == scales.end()) {
      scales.push_back(name);
    }
  }
  return scales;
}

}  // namespace

std::vector<Pass> resolve(Reader& reader, std::vector<ParsedPass> passes) {
  std::set<std::string> names;
  for (bool dropped = true; dropped;) {
    dropped = false;
    names.clear();
    for (const ParsedPass& pass : passes) names.insert(pass.pass.name);
    for (auto it = passes.begin(); it != passes.end();) {
      if (drop_dangling_targets(reader, *it, names)) {
        ++it;
      } else {
        it = passes.erase(it);
        dropped = true;
      }
    }
  }
  std::vector<PassName> order;
  for (const ParsedPass& pass : passes) order.push_back({pass.pass.name, !pass.pass.match.empty()});

  std::vector<Pass> result;
  for (ParsedPass& parsed : passes) {
    std::vector<std::string> scales =
        parsed.scales ? written_scales(reader, parsed, names) : derived_scales(parsed, order);
    Pass pass = std::move(parsed.pass);
    pass.scales = std::move(scales);
    for (ParsedLevel& level : parsed.levels) pass.levels.push_back(std::move(level.level));
    result.push_back(std::move(pass));
  }
  return result;
}

}  // namespace glbudget::manifest::detail
