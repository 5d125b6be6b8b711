#include "reader.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

namespace glbudget::manifest::detail {

Reader::Reader(std::string path, std::vector<Problem>& problems) : path_(std::move(path)), problems_(problems) {
  std::filesystem::path parent = std::filesystem::path(path_).parent_path();
  if (parent.empty()) parent = ".";
  std::error_code error;
  directory_ = std::filesystem::absolute(parent, error);
  if (error) directory_ = parent;
  directory_ = directory_.lexically_normal();
}

std::string Reader::at(const toml::source_region& region) const {
  const toml::source_position begin = region.begin ? region.begin : toml::source_position{1, 1};
  return path_ + ":" + std::to_string(begin.line) + ":" + std::to_string(begin.column);
}

void Reader::report(const toml::source_region& where, const std::string& what, bool fatal) {
  report_at(at(where), what, fatal);
}

void Reader::report_at(const std::string& at, const std::string& what, bool fatal) {
  problems_.push_back(Problem{at + ": " + what, fatal});
}

void Reader::warn_unknown_keys(const toml::table& table, std::initializer_list<std::string_view> known,
                               const std::string& context) {
  for (const auto& [key, node] : in_file_order(table)) {
    if (std::find(known.begin(), known.end(), key->str()) == known.end()) warn_unknown_key(*key, context);
  }
}

void Reader::warn_unknown_key(const toml::key& key, const std::string& context) {
  report(key.source(), "unknown key '" + std::string(key.str()) + "' in " + context + " (ignored)");
}

std::vector<Entry> in_file_order(const toml::table& table) {
  std::vector<Entry> entries;
  for (const auto& [key, node] : table) entries.emplace_back(&key, &node);
  const auto position = [](const Entry& e) {
    const toml::source_position p = e.first->source().begin;
    return std::pair{p.line, p.column};
  };
  std::stable_sort(entries.begin(), entries.end(),
                   [&](const Entry& a, const Entry& b) { return position(a) < position(b); });
  return entries;
}

std::string format_number(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  return std::string(buffer, result.ptr);
}

bool read_text_file(const std::filesystem::path& path, std::string* contents, std::string* why) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    *why = error ? error.message() : std::strerror(ENOENT);
    return false;
  }
  if (!std::filesystem::is_regular_file(path, error)) {
    *why = "not a regular file";
    return false;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    *why = std::strerror(errno);
    return false;
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) {
    *why = "read error";
    return false;
  }
  *contents = std::move(text).str();
  return true;
}

}  // namespace glbudget::manifest::detail
