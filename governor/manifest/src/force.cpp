#include "glbudget/manifest/manifest.hpp"

#include <charconv>
#include <string_view>

namespace glbudget::manifest {
namespace {

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  const auto last = text.find_last_not_of(" \t");
  return text.substr(first, last - first + 1);
}

// Levels separated by commas, or by colons as the log, the selections table and the report
// write a configuration (so a configuration copied from them forces as it reads).
std::vector<std::string_view> split_fields(std::string_view text) {
  std::vector<std::string_view> fields;
  if (trim(text).empty()) return fields;
  for (;;) {
    const auto separator = text.find_first_of(",:");
    fields.push_back(trim(text.substr(0, separator)));
    if (separator == std::string_view::npos) return fields;
    text.remove_prefix(separator + 1);
  }
}

std::string pass_list(const Manifest& m) {
  std::string list;
  for (const Pass& pass : m.passes) list += (list.empty() ? "" : ", ") + pass.name;
  return list;
}

bool fail(std::string* error, std::string text) {
  if (error) *error = std::move(text);
  return false;
}

// One field: a decimal integer, in range for its pass.
bool parse_level(std::string_view field, const Pass& pass, const std::string& text, int* level, std::string* error) {
  long long value = 0;
  const auto [end, status] = std::from_chars(field.data(), field.data() + field.size(), value);
  if (field.empty() || end != field.data() + field.size() ||
      (status != std::errc() && status != std::errc::result_out_of_range)) {
    return fail(error, "GLBUDGET_FORCE='" + text + "': '" + std::string(field) + "' is not a level of pass '" +
                           pass.name + "' (expected an integer)");
  }
  const long long last = static_cast<long long>(pass.levels.size()) - 1;
  if (status == std::errc::result_out_of_range || value < 0 || value > last) {
    return fail(error, "level " + std::string(field) + " of pass '" + pass.name + "' is out of range 0.." +
                           std::to_string(last));
  }
  *level = static_cast<int>(value);
  return true;
}

}  // namespace

std::optional<std::vector<int>> parse_force(const std::string& text, const Manifest& m, std::string* error) {
  const std::vector<std::string_view> fields = split_fields(text);
  if (fields.size() != m.passes.size()) {
    fail(error, "GLBUDGET_FORCE='" + text + "' has " + std::to_string(fields.size()) +
                    (fields.size() == 1 ? " level" : " levels") + "; the manifest has " +
                    std::to_string(m.passes.size()) + (m.passes.size() == 1 ? " pass (" : " passes (") + pass_list(m) +
                    ")");
    return std::nullopt;
  }
  std::vector<int> levels(fields.size());
  for (std::size_t i = 0; i < fields.size(); ++i) {
    if (!parse_level(fields[i], m.passes[i], text, &levels[i], error)) return std::nullopt;
  }
  return levels;
}

}  // namespace glbudget::manifest
