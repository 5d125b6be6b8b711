#include "sysfs.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <system_error>

namespace glbudget::sensors::sysfs {

namespace fs = std::filesystem;

std::optional<std::string> read_text(const fs::path& path, std::string* error, int* error_number) {
  // Plain POSIX calls: this runs on every sample, iostreams would cost more than the read.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int open_errno = errno;
    if (error_number) *error_number = open_errno;
    if (error) *error = path.string() + ": " + std::strerror(open_errno);
    return std::nullopt;
  }
  char buffer[128];
  const ssize_t n = ::read(fd, buffer, sizeof buffer);
  const int read_errno = errno;
  ::close(fd);
  if (n < 0) {
    if (error_number) *error_number = read_errno;
    if (error) *error = path.string() + ": " + std::strerror(read_errno);
    return std::nullopt;
  }
  std::string text(buffer, static_cast<std::size_t>(n));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

Reading read_scaled(const fs::path& path, double scale, ReadingKind kind) {
  Reading reading;
  reading.kind = kind;
  const auto text = read_text(path, &reading.detail);
  if (!text) {
    reading.status = ReadStatus::read_error;
    return reading;
  }
  double value = 0.0;
  const char* end = text->data() + text->size();
  const auto [ptr, ec] = std::from_chars(text->data(), end, value);
  if (ec != std::errc() || ptr != end) {
    reading.status = ReadStatus::garbage;
    reading.detail = path.string() + ": \"" + *text + "\" is not a number";
    return reading;
  }
  reading.value = value * scale;
  return reading;
}

std::vector<fs::path> entries_with_prefix(const fs::path& dir, const std::string& prefix) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().starts_with(prefix)) found.push_back(it->path());
  // Numeric order (hwmon2 before hwmon10), which is the order index=N counts in.
  std::sort(found.begin(), found.end(), [](const fs::path& a, const fs::path& b) {
    const std::string x = a.filename().string(), y = b.filename().string();
    return x.size() != y.size() ? x.size() < y.size() : x < y;
  });
  return found;
}

std::vector<fs::path> hwmon_named(const fs::path& sysfs_root, const std::string& name) {
  std::vector<fs::path> found;
  for (const auto& dir : entries_with_prefix(sysfs_root / "class" / "hwmon", "hwmon"))
    if (read_text(dir / "name") == name) found.push_back(dir);
  return found;
}

}  // namespace glbudget::sensors::sysfs
