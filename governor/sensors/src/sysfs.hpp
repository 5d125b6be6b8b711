#pragma once
// Reading numbers from sysfs attributes (and the fake trees the tests build).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "glbudget/sensors/source.hpp"

namespace glbudget::sensors::sysfs {

// The attribute's text without the trailing newline; empty and `error` (a message) and
// `error_number` (errno) set on failure.
std::optional<std::string> read_text(const std::filesystem::path& path, std::string* error = nullptr,
                                     int* error_number = nullptr);

// Reads a numeric attribute and multiplies it by `scale` (e.g. 1e-6 for µJ -> J).
// Status read_error when the file cannot be read, garbage when it is not a number.
Reading read_scaled(const std::filesystem::path& path, double scale, ReadingKind kind);

// hwmon directories under <root>/class/hwmon whose "name" attribute equals `name`, in
// numeric order.
std::vector<std::filesystem::path> hwmon_named(const std::filesystem::path& sysfs_root, const std::string& name);

// Entries of `dir` whose file name starts with `prefix`, shortest names first, then in
// alphabetical order (so hwmon2 comes before hwmon10); empty if dir is missing.
std::vector<std::filesystem::path> entries_with_prefix(const std::filesystem::path& dir, const std::string& prefix);

}  // namespace glbudget::sensors::sysfs
