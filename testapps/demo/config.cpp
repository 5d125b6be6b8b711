#include "config.hpp"

#include <charconv>

namespace demo {

Config Config::from_index(int index) {
  Config c;
  for (int k = kKnobCount - 1; k >= 0; --k) {
    c.level[k] = index % kLevelCount;
    index /= kLevelCount;
  }
  return c;
}

std::optional<Config> parse_config(std::string_view text) {
  Config c;
  for (int k = 0; k < kKnobCount; ++k) {
    if (text.empty()) return std::nullopt;
    int value = -1;
    auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || value < 0 || value >= kLevelCount) return std::nullopt;
    c.level[k] = value;
    text.remove_prefix(static_cast<size_t>(end - text.data()));
    const bool last = k == kKnobCount - 1;
    if (last != text.empty()) return std::nullopt;
    if (!last) {
      if (text.front() != ',') return std::nullopt;
      text.remove_prefix(1);
    }
  }
  return c;
}

std::string format_config(const Config& config) {
  std::string out;
  for (int k = 0; k < kKnobCount; ++k) {
    if (k) out += ',';
    out += static_cast<char>('0' + config.level[k]);
  }
  return out;
}

namespace {
template <typename T>
T pick(const Config& c, Knob k, T best, T middle, T cheapest) {
  const int level = c[k];
  return level == 0 ? best : level == 1 ? middle : cheapest;
}
}  // namespace

float render_scale(const Config& c) { return pick(c, Knob::Resolution, 1.0f, 0.8f, 0.6f); }
int shading_model(const Config& c) { return pick(c, Knob::BaseShading, 2, 1, 0); }
int reflection_samples(const Config& c) { return pick(c, Knob::Reflections, 64, 16, 0); }
int reflection_kernel_taps(const Config& c) { return pick(c, Knob::Reflections, 9, 1, 0); }
int shadow_map_size(const Config& c, int best) { return pick(c, Knob::Shadows, best, best / 2, best / 4); }
int metal_samples(const Config& c) { return pick(c, Knob::Metals, 60, 6, 2); }
int fxaa_steps(const Config& c) { return pick(c, Knob::Antialiasing, 32, 2, 0); }

}  // namespace demo
