#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "glbudget/sensors/registry.hpp"
#include "glbudget/sensors/sensor.hpp"

namespace glbudget::sensors {

std::optional<std::chrono::milliseconds> parse_sampling_period_ms(std::string_view text) {
  int ms = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), ms);
  if (ec != std::errc() || ptr != text.data() + text.size() || ms < 1 || ms > 1000) return std::nullopt;
  return std::chrono::milliseconds(ms);
}

namespace {

// GLBUDGET_SENSOR_PERIOD_MS: 1..1000, default 5 (see the README for what it costs).
SamplerOptions sampler_options_from_environment() {
  SamplerOptions options;
  const char* value = std::getenv("GLBUDGET_SENSOR_PERIOD_MS");
  if (!value || !*value) return options;
  if (const auto period = parse_sampling_period_ms(value))
    options.period = *period;
  else
    std::fprintf(stderr, "glbudget: GLBUDGET_SENSOR_PERIOD_MS=%s is not 1..1000; using %lld\n", value,
                 static_cast<long long>(options.period.count() / 1'000'000));
  return options;
}

}  // namespace

std::unique_ptr<PowerSensor> open_sensor_from_environment() {
  const SourceEnvironment env = SourceEnvironment::from_process_environment();
  const char* value = std::getenv("GLBUDGET_SENSOR");
  const std::string text = value && *value ? value : "auto";

  std::string error;
  OpenResult opened;
  if (const auto spec = parse_sensor_spec(text, error)) {
    opened = open_source(*spec, env);
    if (!opened.source) error = opened.why_not;
  }
  if (!opened.source) {
    std::fprintf(stderr, "glbudget: GLBUDGET_SENSOR=%s: %s; using auto\n", text.c_str(), error.c_str());
    opened = open_source(SensorSpec{"auto", {}, {}}, env);
  }
  if (!opened.source) {  // cannot happen while cpu is in the auto list, but never crash the host
    std::fprintf(stderr, "glbudget: no power sensor: %s\n", opened.why_not.c_str());
    return nullptr;
  }
  if (text == "auto" || !value)
    std::fprintf(stderr, "glbudget: power sensor %.*s%s: %s\n", static_cast<int>(opened.source->name().size()),
                 opened.source->name().data(), opened.source->is_estimate() ? " (estimate)" : "",
                 opened.source->description().c_str());
  return std::make_unique<PowerSensor>(std::move(opened.source), sampler_options_from_environment());
}

}  // namespace glbudget::sensors
