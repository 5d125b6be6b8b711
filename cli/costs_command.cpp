// glbudget costs: fits the machine's pass-independent costs (a batch, a vertex, a fragment,
// an instruction, a texel access: PlatformCosts) from frame logs of apps that drew several
// configurations, and writes the platform profile with them. The run-time model starts every
// pass from these costs at its level instead of from nothing (analysis/cost_fit.hpp).
//
// Usage in print_help().
#include <cstdio>
#include <fstream>
#include <iostream>
#include <span>
#include <string>
#include <vector>

#include "command.hpp"
#include "glbudget/analysis/frame_log.hpp"
#include "glbudget/analysis/cost_fit.hpp"
#include "glbudget/analysis/resolved_frame.hpp"
#include "glbudget/model/platform_costs.hpp"
#include "glbudget/model/variant_table.hpp"

namespace glbudget::cli {

namespace {

using namespace glbudget::model;
using namespace glbudget::analysis;

constexpr const char* kUsage =
    "usage: glbudget costs --profile PROFILE.json --log LOG.csv --variants VARIANTS.json\n"
    "                      [--log LOG.csv --variants VARIANTS.json ...] [--output OUT.json]\n";

void print_help() {
  std::printf("%s\n", kUsage);
  std::printf(
      "Fits what a batch, a vertex, a fragment, an instruction and a texel access cost on this\n"
      "machine, whatever the pass, over every frame of the logs (GLBUDGET_LOG with a power\n"
      "sensor and a configuration column, each with its variant table), and writes PROFILE with\n"
      "a \"costs\" object to OUT (stdout without --output). The logs should move several shader\n"
      "levels and the render scale. The run-time power model starts each pass from these costs,\n"
      "so its first predictions of other configurations are not a guess. Prints the costs and\n"
      "the in-sample error per log: per frame and of each configuration's mean.\n");
}

int usage() {
  std::fprintf(stderr, "%s", kUsage);
  return 2;
}

struct LogInput {
  std::string log, variants;
};

// The log's frames as the model sees them, each in the configuration it was drawn in.
std::optional<std::vector<ConfiguredSample>> load_samples(const LogInput& input, const VariantTable& table) {
  const auto log = read_frame_log_file(input.log);
  if (!log) return std::nullopt;
  PassNames names(table.space);  // only the samples are kept: the costs are per count, not per pass
  return configured_samples(frames_of_busiest_context(*log), table, names);
}

}  // namespace

int costs_main(std::span<char* const> args) {
  std::string profile_path, output_path;
  std::vector<LogInput> inputs;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string arg = args[i];
    const bool has_value = i + 1 < args.size();
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    }
    if (arg == "--profile" && has_value)
      profile_path = args[++i];
    else if (arg == "--log" && has_value)
      inputs.push_back({args[++i], {}});
    else if (arg == "--variants" && has_value && !inputs.empty() && inputs.back().variants.empty())
      inputs.back().variants = args[++i];
    else if (arg == "--output" && has_value)
      output_path = args[++i];
    else
      return usage();
  }
  if (profile_path.empty() || inputs.empty()) return usage();
  for (const LogInput& input : inputs) {
    if (input.variants.empty()) {
      std::cerr << "glbudget: " << input.log << " needs its --variants table\n";
      return usage();
    }
  }
  auto profile = load_platform_profile(profile_path);
  if (!profile) return 1;

  std::vector<VariantTable> tables;
  std::vector<std::vector<ConfiguredSample>> samples;
  for (const LogInput& input : inputs) {
    auto table = load_variant_table(input.variants);
    if (!table) return 1;
    auto loaded = load_samples(input, *table);
    if (!loaded) return 1;
    tables.push_back(std::move(*table));
    samples.push_back(std::move(*loaded));
  }
  std::vector<CostLog> logs;
  for (std::size_t l = 0; l < inputs.size(); ++l) logs.push_back({samples[l], &tables[l].space});
  const auto fit = fit_platform_costs(logs, *profile);
  if (!fit) {
    std::cerr << "glbudget: no usable frame (power and counts) in any log's configuration space\n";
    return 1;
  }
  std::fprintf(stderr, "costs over %zu frames: batch %.4g, vertex %.4g, fragment %.4g, instruction %.4g, texel %.4g\n",
               fit->samples_used, fit->costs.batch, fit->costs.vertex, fit->costs.fragment, fit->costs.instruction,
               fit->costs.texel);
  std::fprintf(stderr, "in sample, MAPE %%: %-40s %10s %16s\n", "log", "per frame", "per configuration");
  for (std::size_t l = 0; l < inputs.size(); ++l) {
    std::fprintf(stderr, "                  %-40s %10.2f %16.2f\n", inputs[l].log.c_str(),
                 fit->per_frame[l].mape_percent(), fit->per_configuration[l].mape_percent());
  }
  profile->costs = fit->costs;
  const std::string json = platform_profile_to_json(*profile) + "\n";
  if (output_path.empty()) {
    std::fputs(json.c_str(), stdout);
    return 0;
  }
  std::ofstream out(output_path);
  if (!(out << json)) {
    std::cerr << "glbudget: cannot write " << output_path << "\n";
    return 1;
  }
  return 0;
}

}  // namespace glbudget::cli
