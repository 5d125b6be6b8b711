#pragma once
// Private to the parser: passes and levels as read, with where they were written, before
// cross-pass references ("pass:NAME" targets, `scales`) are resolved.
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "reader.hpp"

namespace glbudget::manifest::detail {

struct ParsedLevel {
  Level level;
  std::string label;                   // "level 1 ('80%') of pass 'base'"
  std::string at;                      // where the level is written
  std::vector<std::string> target_at;  // where each of level.targets is written ("" derived)
};

struct ParsedPass {
  Pass pass;                        // its levels are in `levels` until resolve()
  std::vector<ParsedLevel> levels;  // never empty
  // `scales` as written: (name, where); nullopt when absent (derived by resolve()).
  std::optional<std::vector<std::pair<std::string, std::string>>> scales;
};

// One [[pass.level]]; nullopt when invalid (each reason reported, ending "; level dropped",
// or "; pass dropped" for level 0).
std::optional<ParsedLevel> parse_level(Reader& reader, const toml::node& node, std::size_t index,
                                       const std::string& pass_name, bool has_match);

// One [[pass]]; nullopt when dropped. `names` maps the names of earlier passes to where they
// were written, for duplicates; a valid name is added to it even when the pass is dropped.
std::optional<ParsedPass> parse_pass(Reader& reader, const toml::node& node, std::size_t index,
                                     std::map<std::string, std::string>& names);

// Drops "pass:NAME" targets naming no pass (then levels left with nothing to scale, and
// passes that lose level 0, until nothing changes), checks written `scales` and derives the
// missing ones.
std::vector<Pass> resolve(Reader& reader, std::vector<ParsedPass> passes);

}  // namespace glbudget::manifest::detail
