// file:PATH: an external power meter (a source meter, a USB power monitor, a script) that
// appends "timestamp,watts" lines to a regular file or a FIFO. The meter's timestamps only
// have to increase; samples are placed on glbudget's clock when they arrive, so the meter's
// clock needs no synchronisation. Lines that are empty, comments (#) or a header are skipped.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "glbudget/sensors/energy_integrator.hpp"
#include "sources.hpp"

namespace glbudget::sensors {

namespace {

constexpr double kMaxPlausibleW = IntegratorLimits{}.max_plausible_w;

// A meter's line as the stderr message quotes it: control bytes escaped (\xNN), at most 80
// characters, so that binary garbage cannot garble the terminal or flood it.
std::string quoted(std::string_view line) {
  std::string text = "\"";
  for (const char c : line.substr(0, 80)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f && c != '"' && c != '\\') {
      text += c;
    } else {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\x%02x", byte);
      text += escaped;
    }
  }
  return text + (line.size() > 80 ? "\"..." : "\"");
}

bool parse_double(std::string_view text, double& value) {
  while (!text.empty() && text.front() == ' ') text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\r')) text.remove_suffix(1);
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  return ec == std::errc() && ptr == text.data() + text.size() && !text.empty();
}

class FileMeterSource final : public Source {
 public:
  static constexpr std::size_t max_line_bytes = 4096;

  FileMeterSource(std::string path, int fd) : path_(std::move(path)), fd_(fd) {}
  ~FileMeterSource() override { ::close(fd_); }

  std::string_view name() const override { return "file"; }
  std::string description() const override { return "timestamp,watts lines from " + path_; }

  // Returns the mean power of the complete lines that arrived since the previous read.
  Reading read(std::int64_t) override {
    Reading reading;
    reading.kind = ReadingKind::power_w;
    char chunk[4096];
    for (;;) {
      const ssize_t n = ::read(fd_, chunk, sizeof chunk);
      if (n > 0) {
        pending_.append(chunk, static_cast<std::size_t>(n));
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (n < 0 && errno != EAGAIN) {
        reading.status = ReadStatus::read_error;
        reading.detail = path_ + ": " + std::strerror(errno);
        return reading;
      }
      break;  // EAGAIN, or end of file: nothing more for now (a FIFO writer may come back)
    }

    double sum_w = 0.0;
    unsigned good = 0;
    std::size_t line_start = 0;
    for (std::size_t eol; (eol = pending_.find('\n', line_start)) != std::string::npos; line_start = eol + 1) {
      const std::string_view line(pending_.data() + line_start, eol - line_start);
      if (line.empty() || line.front() == '#' || line.starts_with("timestamp")) continue;
      const auto comma = line.find(',');
      double timestamp = 0.0, watts = 0.0;
      if (comma == std::string_view::npos || !parse_double(line.substr(0, comma), timestamp) ||
          !parse_double(line.substr(comma + 1), watts) || !std::isfinite(timestamp) || !std::isfinite(watts) ||
          watts < 0.0) {
        ++reading.discarded_garbage;
        reading.detail = path_ + ": bad line " + quoted(line);
        continue;
      }
      // Judged line by line: averaged with good lines of the same read, an implausible
      // sample would pass the integrator's check on the mean and be charged to frames.
      if (watts > kMaxPlausibleW) {
        ++reading.discarded_garbage;
        reading.detail = path_ + ": implausible power in " + quoted(line);
        continue;
      }
      if (have_timestamp_ && timestamp <= last_timestamp_) {
        ++reading.discarded_backwards;
        reading.detail = path_ + ": timestamp " + quoted(line.substr(0, comma)) + " is not after the previous one";
        continue;
      }
      have_timestamp_ = true;
      last_timestamp_ = timestamp;
      sum_w += watts;
      ++good;
    }
    pending_.erase(0, line_start);
    if (pending_.size() > max_line_bytes) {  // no newline in sight: not a meter's output
      ++reading.discarded_garbage;
      reading.detail = path_ + ": a line longer than " + std::to_string(max_line_bytes) + " bytes";
      pending_.clear();
    }

    if (good == 0) {
      reading.status = ReadStatus::no_new_data;
      return reading;
    }
    reading.value = sum_w / good;
    return reading;
  }

 private:
  std::string path_;
  int fd_;
  std::string pending_;  // an incomplete last line
  bool have_timestamp_ = false;
  double last_timestamp_ = 0.0;
};

}  // namespace

OpenResult open_file(const SensorSpec& spec, const SourceEnvironment&) {
  // Non-blocking: opening a FIFO must not wait for the meter, reading must not wait for data.
  const int fd = ::open(spec.path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return unavailable(spec.path + ": " + std::strerror(errno));
  // A regular file's earlier lines are history, not the present: start at its end.
  // (lseek fails harmlessly on a FIFO.)
  ::lseek(fd, 0, SEEK_END);
  return OpenResult{std::make_unique<FileMeterSource>(spec.path, fd), {}};
}

}  // namespace glbudget::sensors
