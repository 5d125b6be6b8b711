#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>

namespace glbudget::cli {

Progress::Progress(std::FILE* out) : out_(out), terminal_(isatty(fileno(out)) != 0) {}

void Progress::update(double done, double seconds_left, const std::string& what) {
  done = std::clamp(std::isfinite(done) ? done : 0.0, 0.0, 1.0);
  const int left = static_cast<int>(std::ceil(std::max(seconds_left, 0.0)));
  if (!terminal_) {
    std::fprintf(out_, "calibrate: %3.0f %%  %s  (~%d s left)\n", 100.0 * done, what.c_str(), left);
    std::fflush(out_);
    return;
  }
  constexpr int width = 30;
  const int filled = static_cast<int>(std::lround(done * width));
  std::string bar(static_cast<std::size_t>(filled), '#');
  bar.resize(width, '.');
  // \r and erase-line: the bar is redrawn in place.
  std::fprintf(out_, "\r\033[K[%s] %3.0f %%  ~%d s left  %s", bar.c_str(), 100.0 * done, left, what.c_str());
  std::fflush(out_);
  drawn_ = true;
}

void Progress::message(const std::string& text) {
  clear();
  std::fprintf(out_, "%s\n", text.c_str());
  std::fflush(out_);
}

void Progress::clear() {
  if (!drawn_) return;
  std::fprintf(out_, "\r\033[K");
  std::fflush(out_);
  drawn_ = false;
}

}  // namespace glbudget::cli
