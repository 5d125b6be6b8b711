#pragma once
// Private to the parser: where in the manifest a toml++ node is, and the problems found.
#include "toml.hpp"

#include <filesystem>
#include <initializer_list>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "glbudget/manifest/manifest.hpp"

namespace glbudget::manifest::detail {

class Reader {
 public:
  Reader(std::string path, std::vector<Problem>& problems);

  const std::string& path() const { return path_; }
  // Absolute directory of the manifest: relative `replace` files are found from here.
  const std::filesystem::path& directory() const { return directory_; }

  std::string at(const toml::source_region& region) const;  // "PATH:LINE:COLUMN"
  void report(const toml::source_region& where, const std::string& what, bool fatal = false);
  void report_at(const std::string& at, const std::string& what, bool fatal = false);
  // Warns "unknown key 'K' in CONTEXT (ignored)": for `key`, or each key of `table` not in `known`.
  void warn_unknown_key(const toml::key& key, const std::string& context);
  void warn_unknown_keys(const toml::table& table, std::initializer_list<std::string_view> known,
                         const std::string& context);

 private:
  std::string path_;
  std::filesystem::path directory_;
  std::vector<Problem>& problems_;
};

using Entry = std::pair<const toml::key*, const toml::node*>;
// The table's entries in the order they are written (a toml::table iterates sorted by key).
std::vector<Entry> in_file_order(const toml::table& table);

// Shortest text that reads back as `value` (0.8, 1e-05, 3).
std::string format_number(double value);

// The whole file, or false with `why` (strerror or "not a regular file").
bool read_text_file(const std::filesystem::path& path, std::string* contents, std::string* why);

}  // namespace glbudget::manifest::detail
