#include <charconv>
#include <functional>

#include "parsed.hpp"

namespace glbudget::manifest::detail {
namespace {

using Fail = std::function<void(const toml::node&, const std::string&)>;

// A string or an array of strings, each passed to `add`.
void for_each_string(const toml::node& node, const std::string& what, const Fail& fail,
                     const std::function<void(const toml::node&, const std::string&)>& add) {
  if (const auto* text = node.as_string()) return add(node, text->get());
  const toml::array* array = node.as_array();
  if (!array) return fail(node, what + " must be a string or an array of strings");
  for (const toml::node& element : *array) {
    if (const auto* text = element.as_string())
      add(element, text->get());
    else
      fail(element, what + " must be a string or an array of strings");
  }
}

std::optional<uint64_t> parse_hash(const std::string& text) {
  uint64_t hash = 0;
  const char* end = text.data() + text.size();
  if (text.size() != 16 || text.find_first_not_of("0123456789abcdefABCDEF") != std::string::npos) return std::nullopt;
  if (std::from_chars(text.data(), end, hash, 16).ptr != end) return std::nullopt;
  return hash;
}

void parse_match(Reader& reader, const toml::node& node, const std::string& label, Match& match, const Fail& fail) {
  const toml::table* table = node.as_table();
  if (!table) return fail(node, "match must be a table with hash and/or source");
  reader.warn_unknown_keys(*table, {"hash", "source"}, "the match of " + label);
  if (const toml::node* hashes = table->get("hash")) {
    for_each_string(*hashes, "match hash", fail, [&](const toml::node& where, const std::string& text) {
      if (const auto hash = parse_hash(text))
        match.hashes.push_back(*hash);
      else
        fail(where, "match hash '" + text + "' is not 16 hexadecimal digits");
    });
  }
  if (const toml::node* sources = table->get("source")) {
    for_each_string(*sources, "match source", fail, [&](const toml::node& where, const std::string& text) {
      if (!text.empty())
        match.sources.push_back(text);
      else
        fail(where, "match source must not be empty (it would match every program)");
    });
  }
  if (!table->get("hash") && !table->get("source")) fail(node, "match has neither hash nor source");
}

// `has_match`: the pass has a match, valid or not (an invalid one drops the pass anyway; it
// must not also make every "self" target look wrong).
void parse_levels(Reader& reader, const toml::node* node, bool has_match, ParsedPass& out, bool& ok, const Fail& fail) {
  const std::string& name = out.pass.name;
  if (node && !node->as_array()) return fail(*node, "level must be an array of tables ([[pass.level]])");
  if (!node || node->as_array()->empty()) {
    ParsedLevel identity;
    identity.label = "level 0 of pass '" + name + "'";
    out.levels.push_back(std::move(identity));
    return;
  }
  std::size_t index = 0;
  for (const toml::node& element : *node->as_array()) {
    if (auto level = parse_level(reader, element, index, name, has_match)) {
      out.levels.push_back(std::move(*level));
    } else if (index == 0) {
      ok = false;
    }
    ++index;
  }
}

void parse_scales(const toml::node& node, ParsedPass& out, Reader& reader, const Fail& fail) {
  const toml::array* array = node.as_array();
  if (!array) return fail(node, "scales must be an array of pass names");
  out.scales.emplace();
  for (const toml::node& element : *array) {
    if (const auto* text = element.as_string())
      out.scales->emplace_back(text->get(), reader.at(element.source()));
    else
      fail(element, "scales must be an array of pass names");
  }
}

}  // namespace

std::optional<ParsedPass> parse_pass(Reader& reader, const toml::node& node, std::size_t index,
                                     std::map<std::string, std::string>& names) {
  const toml::table* table = node.as_table();
  if (!table) {
    reader.report(node.source(), "pass " + std::to_string(index) + " is not a table; pass dropped");
    return std::nullopt;
  }
  const toml::node* name = table->get("name");
  if (!name) {
    reader.report(node.source(), "pass without a name; pass dropped");
    return std::nullopt;
  }
  if (!name->as_string() || name->as_string()->get().empty()) {
    reader.report(name->source(), "pass name must be a non-empty string; pass dropped");
    return std::nullopt;
  }
  ParsedPass out;
  out.pass.name = name->as_string()->get();
  const std::string label = "pass '" + out.pass.name + "'";
  if (const auto first = names.find(out.pass.name); first != names.end()) {
    reader.report(name->source(),
                  "duplicate pass name '" + out.pass.name + "' (first at " + first->second + "); pass dropped");
    return std::nullopt;
  }
  names.emplace(out.pass.name, reader.at(name->source()));

  bool ok = true;
  const Fail fail = [&](const toml::node& where, const std::string& what) {
    reader.report(where.source(), label + ": " + what + "; pass dropped");
    ok = false;
  };
  const bool has_match = table->get("match") != nullptr;
  bool has_levels = false;
  for (const auto& [key, value] : in_file_order(*table)) {
    const std::string_view key_name = key->str();
    if (key_name == "match") {
      parse_match(reader, *value, label, out.pass.match, fail);
    } else if (key_name == "level") {
      parse_levels(reader, value, has_match, out, ok, fail);
      has_levels = true;
    } else if (key_name == "scales") {
      parse_scales(*value, out, reader, fail);
    } else if (key_name != "name") {
      reader.warn_unknown_key(*key, label);
    }
  }
  if (!has_levels) parse_levels(reader, nullptr, has_match, out, ok, fail);
  if (!ok) return std::nullopt;
  return out;
}

}  // namespace glbudget::manifest::detail
