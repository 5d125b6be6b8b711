// glbudget calibrate: measures this machine's platform profile (P_m, P_M and the saturation
// counts B, V, F of paper §5.2) with one sensor and writes it where `glbudget run` and the shim
// look for it. The steps and how they are judged: calibration_session.hpp and
// governor/analysis/include/glbudget/analysis/calibration.hpp.
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "calibration_session.hpp"
#include "command.hpp"
#include "glbudget/analysis/calibration.hpp"
#include "glbudget/model/platform_profile.hpp"
#include "glbudget/sensors/registry.hpp"
#include "load_runner.hpp"
#include "progress.hpp"
#include "shim_path.hpp"

namespace glbudget::cli {

int calibrate_app_main(std::span<char* const> args);  // calibrate_app.cpp

namespace {

namespace fs = std::filesystem;

void print_help() {
  std::printf(
      "usage: glbudget calibrate [--sensor S] [--output PATH] [--fps R] [--quick] [--verbose]\n"
      "       glbudget calibrate --app [--config MANIFEST] [--frames N] [--output PATH] -- APP [ARGS...]\n\n"
      "Measures the platform profile the power model needs, once per machine and sensor: P_m (frames\n"
      "that draw nothing), then power against batches, vertices and fragments per frame, each swept\n"
      "in doubling steps at R frames per second (default 30) until power stops rising: P_M is the\n"
      "highest plateau, B, V and F where each curve reaches 95 %% of its rise. Takes under a\n"
      "minute (--quick: a few seconds, coarser). Ctrl-C writes what was measured so far, with\n"
      "defaults for the rest. The profile goes to --output, else $GLBUDGET_PROFILE, else\n"
      "$XDG_CACHE_HOME/glbudget/<sensor>.json. --sensor: as GLBUDGET_SENSOR (default: it, or auto).\n"
      "--verbose prints every step.\n"
      "--app measures an app's manifest levels instead (glbudget calibrate --app --help).\n");
}

struct Options {
  std::string sensor;
  std::string output;
  double fps = 30.0;
  bool quick = false;
  bool verbose = false;
};

// Empty on bad input, after one `glbudget:` line; exit_status 0 for --help.
std::optional<Options> parse(std::span<char* const> args, int& exit_status) {
  Options o;
  if (const char* env = std::getenv("GLBUDGET_SENSOR"); env && *env) o.sensor = env;
  exit_status = 2;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string arg = args[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= args.size()) {
        std::fprintf(stderr, "glbudget: calibrate: %s needs a value\n", arg.c_str());
        return nullptr;
      }
      return args[++i];
    };
    if (arg == "--help" || arg == "-h") {
      print_help();
      exit_status = 0;
      return std::nullopt;
    } else if (arg == "--quick") {
      o.quick = true;
    } else if (arg == "--verbose") {
      o.verbose = true;
    } else if (arg == "--sensor" || arg == "--output" || arg == "--fps") {
      const char* v = value();
      if (!v) return std::nullopt;
      if (arg == "--sensor")
        o.sensor = v;
      else if (arg == "--output")
        o.output = v;
      else {
        char* end = nullptr;
        o.fps = std::strtod(v, &end);
        if (end == v || *end || !(o.fps >= 1.0 && o.fps <= 1000.0)) {
          std::fprintf(stderr, "glbudget: calibrate: --fps %s is not a frame rate in [1, 1000]\n", v);
          return std::nullopt;
        }
      }
    } else {
      std::fprintf(stderr, "glbudget: calibrate: unknown argument %s (see glbudget calibrate --help)\n", arg.c_str());
      return std::nullopt;
    }
  }
  if (o.sensor.empty()) o.sensor = "auto";
  return o;
}

struct Sensor {
  std::string value;  // for GLBUDGET_SENSOR: auto resolved, so the load uses what was named
  std::string kind;   // for the profile's file name
  std::string description;
};

std::optional<Sensor> open_sensor(const std::string& text) {
  std::string error;
  const auto spec = sensors::parse_sensor_spec(text, error);
  if (!spec) {
    std::fprintf(stderr, "glbudget: calibrate: sensor %s: %s\n", text.c_str(), error.c_str());
    return std::nullopt;
  }
  const sensors::OpenResult opened =
      sensors::open_source(*spec, sensors::SourceEnvironment::from_process_environment());
  if (!opened.source) {
    std::fprintf(stderr, "glbudget: calibrate: sensor %s is not available: %s\n", text.c_str(), opened.why_not.c_str());
    return std::nullopt;
  }
  Sensor s;
  s.kind = opened.source->name();
  s.value = spec->kind == "auto" ? s.kind : text;
  s.description = opened.source->description();
  return s;
}

// Creates the profile's directory and checks that a file can be written there, before a minute
// of measuring.
bool check_writable(const fs::path& path) {
  std::error_code ec;
  if (path.has_parent_path()) fs::create_directories(path.parent_path(), ec);
  const fs::path probe = path.string() + ".tmp" + std::to_string(getpid());
  std::ofstream out(probe);
  const bool ok = static_cast<bool>(out);
  out.close();
  fs::remove(probe, ec);
  if (!ok || fs::is_directory(path, ec))
    std::fprintf(stderr, "glbudget: calibrate: cannot write the profile %s\n", path.c_str());
  return ok && !fs::is_directory(path, ec);
}

bool write_profile(const fs::path& path, const model::PlatformProfile& profile) {
  const fs::path temp = path.string() + ".tmp" + std::to_string(getpid());
  {
    std::ofstream out(temp);
    out << model::platform_profile_to_json(profile) << "\n";
    if (!out) return false;
  }
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) fs::remove(temp, ec);
  return !ec;
}

void print_sweeps(const CalibrationSession& session) {
  for (const SweepRecord& sweep : session.sweeps()) {
    std::printf("%s sweep:\n", sweep.name);
    for (const MeasuredStep& s : sweep.steps)
      std::printf("  %14.0f per frame  %8.2f W  %4lld frames%s\n", s.count, s.power_w, s.frames,
                  s.late ? "  late" : "");
  }
}

void print_result(const analysis::CalibrationResult& r, const CalibrationSession& session) {
  auto is_default = [&](const char* field) {
    for (const std::string& d : r.defaults)
      if (d == field) return true;
    return false;
  };
  const analysis::Saturation* saturations[3] = {&r.batches, &r.vertices, &r.fragments};
  const double values[3] = {r.profile.saturation_batches, r.profile.saturation_vertices,
                            r.profile.saturation_fragments};
  const char* symbols[3] = {"B", "V", "F"};
  const char* names[3] = {"batches", "vertices", "fragments"};
  std::printf("P_m %10.2f W    %s\n", r.profile.p_min_w,
              is_default("p_min_w") ? "default: not measured" : "frames that draw nothing (one clipped triangle)");
  std::printf("P_M %10.2f W    %s\n", r.profile.p_max_w,
              is_default("p_max_w") ? "default: not measured" : ("the " + r.p_max_from + " sweep's plateau").c_str());
  for (int i = 0; i < 3; ++i) {
    const std::string field = std::string("saturation.") + names[i];
    const std::size_t steps = i < static_cast<int>(session.sweeps().size()) ? session.sweeps()[i].steps.size() : 0;
    const bool fallback = is_default(field.c_str());
    std::printf("%s   %12.0f    %s per frame: %s%s%s (%zu steps)\n", symbols[i], values[i], names[i],
                fallback ? "default (measured: " : "", analysis::to_string(saturations[i]->kind), fallback ? ")" : "",
                steps);
  }
}

}  // namespace

int calibrate_main(std::span<char* const> args) {
  for (char* arg : args) {
    if (std::string_view(arg) == "--") break;
    if (std::string_view(arg) == "--app") return calibrate_app_main(args);
  }
  int status = 0;
  const std::optional<Options> options = parse(args, status);
  if (!options) return status;
  const std::optional<Sensor> sensor = open_sensor(options->sensor);
  if (!sensor) return 2;

  std::string output = options->output;
  if (output.empty())
    if (const char* env = std::getenv("GLBUDGET_PROFILE"); env && *env) output = env;
  if (output.empty()) output = default_profile(sensor->value);
  if (output.empty()) {
    std::fprintf(stderr,
                 "glbudget: calibrate: nowhere to write the profile: set XDG_CACHE_HOME or HOME, or pass --output\n");
    return 2;
  }
  const fs::path path = fs::absolute(output);
  if (!check_writable(path)) return 2;

  const std::string shim = find_shim();
  if (shim.empty()) {
    std::fprintf(stderr, "glbudget: calibrate: libglbudget.so not found beside this program (set GLBUDGET_SHIM)\n");
    return 2;
  }
  const std::string load = find_helper("calibrate_load", "testapps/calibrate_load", "GLBUDGET_CALIBRATE_LOAD");
  if (load.empty()) {
    std::fprintf(stderr,
                 "glbudget: calibrate: calibrate_load not found beside this program (set GLBUDGET_CALIBRATE_LOAD)\n");
    return 2;
  }
  std::error_code ec;
  const fs::path temp = fs::temp_directory_path(ec);
  std::string work_dir = ((ec ? fs::path("/tmp") : temp) / "glbudget-calibrate-XXXXXX").string();
  if (!mkdtemp(work_dir.data())) {
    std::fprintf(stderr, "glbudget: calibrate: cannot make a temporary directory %s\n", work_dir.c_str());
    return 1;
  }

  SessionSettings settings;
  settings.fps = options->fps;
  if (options->quick) {
    settings.idle_s = 0.4;
    settings.step_s = 0.15;
    settings.factor = 4.0;
    settings.budget_s = 20.0;
    settings.max_steps = 12;
  }
  std::printf("sensor %s (%s); sweeps paced at %g fps\n", sensor->kind.c_str(), sensor->description.c_str(),
              settings.fps);
  std::fflush(stdout);
  catch_interrupts();
  LoadRunner runner(load, shim, sensor->value, work_dir);
  Progress progress(stderr);
  CalibrationSession session(runner, progress, settings);
  std::string error;
  const bool ok = session.run(error);
  progress.clear();
  fs::remove_all(work_dir, ec);
  if (!ok) {
    std::fprintf(stderr, "glbudget: calibrate: %s\n", error.c_str());
    return 1;
  }

  analysis::CalibrationResult result = analysis::calibrate_profile(session.measurements());
  model::PlatformProfile& profile = result.profile;
  for (double* count : {&profile.saturation_batches, &profile.saturation_vertices, &profile.saturation_fragments})
    *count = std::max(1.0, std::round(*count));
  if (options->verbose) print_sweeps(session);
  print_result(result, session);
  const auto is_default = [&](const std::string& field) {
    return std::find(result.defaults.begin(), result.defaults.end(), field) != result.defaults.end();
  };
  if (is_default("p_min_w") || is_default("p_max_w")) {
    // Only reachable when interrupted: without both powers a profile is of no use.
    std::fprintf(stderr, "glbudget: calibrate: interrupted before P_m and P_M were measured; no profile written\n");
    return 130;
  }
  if (!write_profile(path, profile)) {
    std::fprintf(stderr, "glbudget: calibrate: cannot write the profile %s\n", path.c_str());
    return 1;
  }
  std::printf("measured in %.1f s; profile written to %s\n", session.seconds(), path.c_str());
  if (interrupted()) {
    std::string list;
    for (const std::string& d : result.defaults) list += (list.empty() ? "" : ", ") + d;
    std::fprintf(stderr, "glbudget: calibrate: interrupted: the profile holds the steps done so far%s%s\n",
                 list.empty() ? "" : "; defaults: ", list.c_str());
    return 130;
  }
  return 0;
}

}  // namespace glbudget::cli
