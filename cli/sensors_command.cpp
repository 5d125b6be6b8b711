// glbudget sensors: which power sensors this machine offers, what each reads now, why the
// others are unavailable, and which one GLBUDGET_SENSOR (default auto) would use.
#include <charconv>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "command.hpp"
#include "glbudget/sensors/registry.hpp"
#include "glbudget/sensors/sensor.hpp"

namespace glbudget::cli {

namespace {

using namespace glbudget::sensors;

constexpr int default_window_ms = 250;

void print_help() {
  std::printf(
      "usage: glbudget sensors [--window MS]\n\n"
      "Lists every power sensor glbudget knows, reads the available ones for MS milliseconds\n"
      "(default %d) and shows their mean power, and says why the others are unavailable.\n"
      "GLBUDGET_SENSOR selects the one the shim uses (default auto); see the README for its\n"
      "syntax. GLBUDGET_SYSFS_ROOT and GLBUDGET_NVML_LIBRARY override where sensors are looked\n"
      "for.\n",
      default_window_ms);
}

int parse_window(std::span<char* const> args) {
  int window_ms = default_window_ms;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string_view arg = args[i];
    if (arg == "--window" && i + 1 < args.size()) {
      const std::string_view value = args[++i];
      int parsed = 0;
      const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), parsed);
      if (ec == std::errc() && ptr == value.data() + value.size() && parsed >= 20 && parsed <= 60000)
        window_ms = parsed;
      else
        std::fprintf(stderr, "glbudget: --window %s is not 20..60000 ms; using %d\n", args[i], default_window_ms);
    } else {
      std::fprintf(stderr, "glbudget: sensors: ignoring unknown argument \"%s\"\n", args[i]);
    }
  }
  return window_ms;
}

struct Row {
  std::string label;
  std::unique_ptr<PowerSensor> sensor;  // null when unavailable
  std::string why_not;
};

void print_row(const Row& row, const FrameEnergy& frame) {
  if (!row.sensor) {
    std::printf("  %-8s unavailable  %s\n", row.label.c_str(), row.why_not.c_str());
    return;
  }
  char reading[64];
  if (frame.valid)
    std::snprintf(reading, sizeof reading, "%8.2f W%s", frame.mean_power_w, frame.estimate ? " (estimate)" : "");
  else
    std::snprintf(reading, sizeof reading, "no reading");  // nothing moved, or every read failed
  std::printf("  %-8s %-22s %s", row.label.c_str(), reading, row.sensor->description().c_str());
  if (const FaultCounts f = row.sensor->faults(); f.total() > 0)
    std::printf("  [dropped: %llu read errors, %llu garbage, %llu backwards, %llu stalled]",
                static_cast<unsigned long long>(f.read_error), static_cast<unsigned long long>(f.garbage),
                static_cast<unsigned long long>(f.backwards), static_cast<unsigned long long>(f.stalled));
  std::printf("\n");
}

}  // namespace

int sensors_main(std::span<char* const> args) {
  for (const std::string_view arg : args)
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    }
  const int window_ms = parse_window(args);
  const SourceEnvironment env = SourceEnvironment::from_process_environment();

  std::vector<Row> rows;
  for (auto& probe : probe_all(env)) {
    Row row{probe.kind, nullptr, probe.opened.why_not};
    if (probe.opened.source) row.sensor = std::make_unique<PowerSensor>(std::move(probe.opened.source));
    rows.push_back(std::move(row));
  }
  const char* chosen = std::getenv("GLBUDGET_SENSOR");
  const std::string chosen_text = chosen && *chosen ? chosen : "auto";
  std::string chosen_error;
  const auto chosen_spec = parse_sensor_spec(chosen_text, chosen_error);
  if (chosen_spec && chosen_spec->kind == "file") {  // not probed by default: needs a path
    auto opened = open_source(*chosen_spec, env);
    Row row{"file", nullptr, opened.why_not};
    if (opened.source) row.sensor = std::make_unique<PowerSensor>(std::move(opened.source));
    rows.push_back(std::move(row));
  }

  // Let every sampler collect a couple of samples, then measure one window.
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  for (auto& row : rows)
    if (row.sensor) row.sensor->on_swap(monotonic_now_ns());
  std::this_thread::sleep_for(std::chrono::milliseconds(window_ms));
  std::printf("power sensors (mean over %d ms; cpu is this glbudget process, near idle):\n", window_ms);
  for (auto& row : rows) print_row(row, row.sensor ? row.sensor->on_swap(monotonic_now_ns()) : FrameEnergy{});

  if (!chosen_spec) {
    std::printf("\nGLBUDGET_SENSOR=%s is invalid (%s); the shim would use auto\n", chosen_text.c_str(),
                chosen_error.c_str());
    return 0;
  }
  const auto opened = open_source(*chosen_spec, env);
  if (opened.source)
    std::printf("\nGLBUDGET_SENSOR=%s uses: %.*s%s\n", chosen_text.c_str(),
                static_cast<int>(opened.source->name().size()), opened.source->name().data(),
                opened.source->is_estimate() ? " (an estimate, not a measurement)" : "");
  else
    std::printf("\nGLBUDGET_SENSOR=%s is unavailable (%s); the shim would use auto\n", chosen_text.c_str(),
                opened.why_not.c_str());
  return 0;
}

}  // namespace glbudget::cli
