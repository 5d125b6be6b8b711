// glbudget replay: replays a frame log (GLBUDGET_LOG with power columns) through the run-time
// power model and
// the Vatjus-Anttila 2013 baseline, and prints both models' prediction errors on the same
// frames: MAPE and mean/max error relative to P_M - P_m, for frames in the fitted
// configuration, for frames predicted by reusing the coefficients, and for the next
// configuration predicted before each switch; per frame and averaged over --average frames,
// beside the noise floor of the recording (see replay.hpp).
//
// Usage in print_help().
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <span>
#include <string>

#include "command.hpp"
#include "glbudget/analysis/replay.hpp"

namespace glbudget::cli {

namespace {

using namespace glbudget::model;
using namespace glbudget::analysis;

void print_row(const char* model, const char* frames, const char* scope, const PredictionError& e) {
  std::printf("%-16s %-8s %-10s %7zu %9.2f %14.2f %13.2f\n", model, frames, scope, e.count(), e.mape_percent(),
              100.0 * e.mean_share_of_range(), 100.0 * e.max_share_of_range());
}

void print_rows(const char* model, const char* frames, const ReplayErrors& e, const std::string& averaged) {
  print_row(model, frames, "per frame", e.per_frame);
  print_row(model, frames, averaged.c_str(), e.averaged);
}

// A positive number, or the default with one `glbudget:` line.
template <typename T>
T parse_or_keep(const char* flag, const char* text, T fallback) {
  char* end = nullptr;
  const double value = std::strtod(text, &end);
  if (end == text || *end != '\0' || !(value > 0.0)) {
    std::cerr << "glbudget: " << flag << " needs a positive number, not \"" << text << "\"; using " << fallback << "\n";
    return fallback;
  }
  return static_cast<T>(value);
}

// A whole number, 0 included; the fallback for anything else, with a message.
std::size_t parse_count(const char* flag, const char* text, std::size_t fallback) {
  char* end = nullptr;
  errno = 0;
  const unsigned long long value = std::strtoull(text, &end, 10);
  if (end == text || *end != '\0' || errno != 0 || text[0] == '-') {
    std::cerr << "glbudget: " << flag << " needs a whole number, not \"" << text << "\"; using " << fallback << "\n";
    return fallback;
  }
  return static_cast<std::size_t>(value);
}

constexpr const char* kUsage =
    "usage: glbudget replay LOG.csv --profile PROFILE.json [--variants VARIANTS.json]\n"
    "                       [--fit-window N] [--check-window N] [--threshold SHARE] [--average N]\n"
    "                       [--paper] [--remember N] [--frames-csv PATH]\n";

void print_help() {
  std::printf("%s\n", kUsage);
  std::printf(
      "Replays a frame log written by the shim (GLBUDGET_LOG, with a power sensor) through the\n"
      "run-time power model as the governor would run it, and through the Vatjus-Anttila 2013\n"
      "baseline, and prints both models' errors on the same frames (MAPE, and mean and max error\n"
      "as a share of P_M - P_m): fitted and reused frames, all frames, switches between\n"
      "configurations, per frame and over --average frames (30), beside the recording's noise\n"
      "floor. The profile gives P_m, P_M and the saturation counts; the variant table which\n"
      "programs are which level of which pass (tests/data/logs/README.md). Options:\n"
      "  --fit-window N, --check-window N, --threshold SHARE   the online fitter's (30, 10, 0.1)\n"
      "  --paper            the paper's path only: no fit over several configurations\n"
      "  --remember N       a configuration whose frames have left the history enters its fits as\n"
      "                     N frames of their mean (30); 0: forgotten\n"
      "  --frames-csv PATH  every scored frame: measured power and both predictions\n");
}

int usage() {
  std::fprintf(stderr, "%s", kUsage);
  return 2;
}

}  // namespace

int replay_main(std::span<char* const> args) {
  std::string log_path, profile_path, variants_path, frames_csv;
  FitSettings settings;
  ReplayOptions options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    }
    if (arg == "--profile" && has_value)
      profile_path = args[++i];
    else if (arg == "--variants" && has_value)
      variants_path = args[++i];
    else if (arg == "--fit-window" && has_value)
      settings.fitting_window = parse_or_keep("--fit-window", args[++i], settings.fitting_window);
    else if (arg == "--check-window" && has_value)
      settings.check_window = parse_or_keep("--check-window", args[++i], settings.check_window);
    else if (arg == "--threshold" && has_value)
      settings.refit_threshold = parse_or_keep("--threshold", args[++i], settings.refit_threshold);
    else if (arg == "--paper")
      options.history.enabled = false;
    else if (arg == "--remember" && has_value)
      options.history.remembered_frames = parse_count("--remember", args[++i], options.history.remembered_frames);
    else if (arg == "--frames-csv" && has_value)
      frames_csv = args[++i];
    else if (arg == "--average" && has_value)
      options.average_frames = parse_or_keep("--average", args[++i], options.average_frames);
    else if (log_path.empty() && arg.rfind("--", 0) != 0)
      log_path = arg;
    else
      return usage();
  }
  if (log_path.empty() || profile_path.empty()) return usage();

  const auto profile = load_platform_profile(profile_path);
  const auto log = read_frame_log_file(log_path);
  if (!profile || !log) return 1;
  VariantTable variants;
  if (!variants_path.empty()) {
    auto loaded = load_variant_table(variants_path);
    if (!loaded) return 1;
    variants = std::move(*loaded);
  }

  const auto frames = frames_of_busiest_context(*log);
  const ReplayReport report = replay_frames(frames, *profile, variants, settings, options);
  std::printf(
      "%s: %zu frames (%zu unusable), %zu configuration runs of %zu configurations, %zu fits "
      "(%zu over several configurations, %zu failed checks), chi %.4g psi %.4g\n",
      log_path.c_str(), report.frames, report.frames_unusable, report.configuration_runs, variants.space.size(),
      report.fits, report.history_fits, report.checks_failed, report.reuse.chi, report.reuse.psi);
  const std::string averaged = std::to_string(options.average_frames) + "-frame";
  std::printf("%-16s %-8s %-10s %7s %9s %14s %13s\n", "model", "frames", "scope", "count", "MAPE %", "mean %range",
              "max %range");
  print_rows("ours", "fitted", report.ours_fitted, averaged);
  print_rows("ours", "reused", report.ours_reused, averaged);
  print_row("ours", "switch", "next run", report.ours_switch);
  print_rows("ours", "all", report.ours_all, averaged);
  print_rows("vatjus-anttila", "fitted", report.baseline_fitted, averaged);
  print_rows("vatjus-anttila", "reused", report.baseline_reused, averaged);
  print_row("vatjus-anttila", "switch", "next run", report.baseline_switch);
  print_rows("vatjus-anttila", "all", report.baseline_all, averaged);
  print_row("no change", "switch", "next run", report.unchanged_switch);
  print_rows("noise floor", "all", report.floor, averaged);
  if (!frames_csv.empty()) {
    if (FILE* out = std::fopen(frames_csv.c_str(), "w")) {
      std::fprintf(out, "frame,run,fitted,measured_w,ours_w,baseline_w\n");
      for (const ReplayFrame& f : report.scored) {
        std::fprintf(out, "%llu,%zu,%d,%.4f,%.4f,%.4f\n", static_cast<unsigned long long>(f.frame), f.run,
                     f.fitted_here ? 1 : 0, f.measured, f.ours, f.baseline);
      }
      std::fclose(out);
    } else {
      std::cerr << "glbudget: cannot write " << frames_csv << "\n";
    }
  }
  std::printf("\nlast model: per-frame load %.4g; k_b, k_v, k_f per pass\n", report.model.frame_alpha());
  for (model::PassIndex pass = 0; pass < report.model.coefficients().size(); ++pass) {
    const model::PassCoefficients* k = report.model.find(pass);
    if (k) std::printf("  %-20s %10.4g %10.4g %10.4g\n", report.names.name(pass).c_str(), k->k_b, k->k_v, k->k_f);
  }
  std::printf("\nper configuration run: scored frames, mean measured, ours, baseline (W)\n");
  for (const ReplayRun& run : report.runs) {
    std::string configuration;
    for (int level : run.configuration) configuration += (configuration.empty() ? "" : ":") + std::to_string(level);
    std::printf("  %-14s %4zu %8.2f %8.2f %8.2f%s\n", configuration.c_str(), run.scored_frames, run.measured_w,
                run.ours_w, run.baseline_w, run.fitted_here ? "  (fitted)" : "");
  }
  std::printf("\nper switch, into run: measured, ours, baseline, no change (W)\n");
  for (const ReplaySwitch& change : report.switches) {
    std::printf("  %-14zu %8.2f %8.2f %8.2f %8.2f\n", change.to_run + 1, change.measured_w, change.ours_w,
                change.baseline_w, change.unchanged_w);
  }
  return 0;
}

}  // namespace glbudget::cli
