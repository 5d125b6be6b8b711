// A rendering configuration: one quality level per pass, 0 = best, 2 = cheapest
// (the paper's Table 2). 3^6 = 729 configurations.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace demo {

enum class Knob { Resolution, BaseShading, Reflections, Shadows, Metals, Antialiasing };
inline constexpr int kKnobCount = 6;
inline constexpr int kLevelCount = 3;
inline constexpr int kConfigCount = 729;  // kLevelCount^kKnobCount
// The shadow map's side at the best level (--shadow-size; the paper's Table 2).
inline constexpr int kShadowMapSize = 2048;

struct Config {
  std::array<int, kKnobCount> level{};  // all best by default
  int operator[](Knob k) const { return level[static_cast<int>(k)]; }
  int& operator[](Knob k) { return level[static_cast<int>(k)]; }
  bool operator==(const Config&) const = default;

  static Config best() { return {}; }
  static Config cheapest() { return {{2, 2, 2, 2, 2, 2}}; }
  // The index-th of the 729 configurations (first knob varies slowest).
  static Config from_index(int index);
};

// "0,1,2,0,0,1" -> Config; nullopt when malformed (wrong count, level outside 0..2).
std::optional<Config> parse_config(std::string_view text);
std::string format_config(const Config& config);  // "0,1,2,0,0,1"

// What each level means (Table 2), used by the passes.
float render_scale(const Config& c);          // 1.0, 0.8, 0.6
int shading_model(const Config& c);           // 2 microfacet, 1 improved point lights, 0 cheap spec
int reflection_samples(const Config& c);      // 64, 16, 0 (off)
int reflection_kernel_taps(const Config& c);  // 9, 1, 0 (off)
int metal_samples(const Config& c);           // 60, 6, 2
int fxaa_steps(const Config& c);              // 32, 2, 0 (off)
// best, best / 2, best / 4 texels square: 2048, 1024, 512 by default (--shadow-size).
int shadow_map_size(const Config& c, int best = kShadowMapSize);

}  // namespace demo
