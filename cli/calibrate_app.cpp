// glbudget calibrate --app: measures what each quality level of an app's manifest costs per
// invocation (executed instructions and texel accesses, per vertex and per fragment), so that
// the power model predicts the saving of levels that change shaders, not only of those that
// change how much is drawn. One run of the app under the shim with instrumentation on and a
// GLBUDGET_FORCE list that draws every pass at level 0, then 1, then 2 ... for N frames each;
// the shim's dump says which program drew each level (variants.json) and what each program
// executed. Then, with a profile, each level's power (measure_power), and each level's error
// against the best, as the ratio k of the paper's §6.2 (measure_error_ratios). Writes the
// variant table (governor/model/variant_table.hpp) the shim reads.
#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <span>
#include <sstream>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "calibrate_errors.hpp"
#include "glbudget/manifest/manifest.hpp"
#include "glbudget/model/configured_sample.hpp"
#include "glbudget/analysis/frame_log.hpp"
#include "glbudget/analysis/cost_fit.hpp"
#include "glbudget/analysis/resolved_frame.hpp"
#include "glbudget/model/platform_costs.hpp"
#include "glbudget/model/platform_profile.hpp"
#include "glbudget/model/variant_table.hpp"
#include "glbudget/sensors/profile_path.hpp"
#include "shim_path.hpp"

namespace glbudget::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using nlohmann::ordered_json;

constexpr const char* kUsage =
    "usage: glbudget calibrate --app [--config MANIFEST] [--frames N] [--power-frames N] [--error-probes N]\n"
    "                                [--fps R] [--sensor S] [--profile P] [--timeout S] [--output PATH]\n"
    "                                -- APP [ARGS...]\n";

void print_help() {
  std::printf("%s\n", kUsage);
  std::printf(
      "Measures, once per app and manifest, what each level of each manifest pass costs per\n"
      "invocation: executed instructions per vertex and per fragment, texel accesses per fragment\n"
      "(shader instrumentation, glbudget's own GLSL rewrite). The app runs once under the shim with\n"
      "every pass at level 0 for N frames (default 30), then at level 1, and so on, and is stopped\n"
      "(SIGTERM) once every level has drawn; an app that exits earlier is measured up to there. Its\n"
      "frames run about twice as slowly while it is measured; nothing it draws is changed otherwise.\n"
      "MANIFEST: --config, else $GLBUDGET_CONFIG, else $XDG_CONFIG_HOME/glbudget/<app>.toml.\n"
      "The table goes to --output, else $XDG_CACHE_HOME/glbudget/<app>.variants.json, where the shim\n"
      "looks for it (GLBUDGET_COSTS overrides); with it, a budget's model predicts the saving of\n"
      "levels that simplify shaders. --timeout: stop the app after S seconds whatever it drew\n"
      "(default 600) in each of the two runs.\n\n"
      "Then, with a platform profile (--profile, else $GLBUDGET_PROFILE, else the sensor's from\n"
      "`glbudget calibrate`), the app runs again, uninstrumented, with the sensor (--sensor, else\n"
      "$GLBUDGET_SENSOR, else auto): level 0 everywhere, then each level of each pass alone, then\n"
      "the cheapest, in short blocks round after round, the second half of the rounds the first\n"
      "half's mirror image (a drift linear in time cancels), keeping about --power-frames - 2\n"
      "frames of each (default 20, at least 3: the first two after each switch are left out; 0\n"
      "skips this run), paced at --fps R if given (as the app will run under a budget).\n"
      "From those frames' power the costs of a batch, vertex, fragment, instruction and texel\n"
      "access in this app's frames are fitted (as `glbudget costs` does) and kept in the table;\n"
      "the model starts from them.\n\n"
      "Last, the app runs at its best with quality probes every other frame, each level below the\n"
      "best of each pass in turn, --error-probes times each (default 4; 0 skips this run): each\n"
      "level's error (1 - SSIM against the best) over its pass's cheapest level's is the ratio k the\n"
      "governor scales the cheapest level's error by while it runs (\"error_ratio\" in the table;\n"
      "without it, the manifest's `error` values or l / lmax).\n");
}

struct Options {
  std::string manifest, output, sensor, profile, fps;
  unsigned frames = 30;
  unsigned power_frames = 20;
  unsigned error_probes = 4;
  double timeout_s = 600.0;
  std::vector<char*> app;  // argv, null-terminated
};

std::optional<Options> parse(std::span<char* const> args, int& status) {
  Options o;
  status = 2;
  if (const char* env = std::getenv("GLBUDGET_CONFIG"); env && *env) o.manifest = env;
  if (const char* env = std::getenv("GLBUDGET_SENSOR"); env && *env) o.sensor = env;
  if (const char* env = std::getenv("GLBUDGET_PROFILE"); env && *env) o.profile = env;
  if (const char* env = std::getenv("GLBUDGET_FPS"); env && *env) o.fps = env;
  std::size_t i = 0;
  for (; i < args.size(); ++i) {
    const std::string arg = args[i];
    if (arg == "--") {
      ++i;
      break;
    }
    if (arg == "--help" || arg == "-h") {
      print_help();
      status = 0;
      return std::nullopt;
    }
    if (arg == "--app") continue;
    static const std::vector<std::string> kValued = {"--config",  "--frames", "--power-frames",
                                                     "--timeout", "--output", "--error-probes",
                                                     "--fps",     "--sensor", "--profile"};
    if (i + 1 >= args.size() || std::find(kValued.begin(), kValued.end(), arg) == kValued.end()) {
      std::fprintf(stderr, "glbudget: calibrate --app: %s %s\n%s", arg.c_str(),
                   i + 1 >= args.size() ? "needs a value" : "is not an option", kUsage);
      return std::nullopt;
    }
    const std::string value = args[++i];
    if (arg == "--config")
      o.manifest = value;
    else if (arg == "--output")
      o.output = value;
    else if (arg == "--sensor")
      o.sensor = value;
    else if (arg == "--profile")
      o.profile = value;
    else {
      char* end = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      const bool frames = arg == "--frames" || arg == "--power-frames" || arg == "--error-probes";
      const double least = arg == "--frames" ? 1 : 0;
      // The power run leaves out the first two frames after each switch (settled_samples): with
      // fewer than three a configuration, only the first one would be measured.
      const bool too_few_to_settle = arg == "--power-frames" && (v == 1 || v == 2);
      const bool bad = end == value.c_str() || *end || !std::isfinite(v) ||
                       (frames ? (v < least || v > 100000 || v != std::floor(v) || too_few_to_settle)
                               : (v <= 0 || (arg == "--fps" && v > 10000)));
      if (bad) {
        const char* wanted = !frames ? (arg == "--fps" ? "a frame rate in (0, 10000]" : "a number of seconds > 0")
                             : least ? "a number of frames in [1, 100000]"
                             : arg == "--power-frames"
                                 ? "0 (no power run) or a number of frames in [3, 100000] (the first two after each "
                                   "switch are left out)"
                                 : "a number of frames in [0, 100000]";
        std::fprintf(stderr, "glbudget: calibrate --app: %s %s is not %s\n", arg.c_str(), value.c_str(), wanted);
        return std::nullopt;
      }
      if (arg == "--frames")
        o.frames = static_cast<unsigned>(v);
      else if (arg == "--power-frames")
        o.power_frames = static_cast<unsigned>(v);
      else if (arg == "--error-probes")
        o.error_probes = static_cast<unsigned>(v);
      else if (arg == "--fps")
        o.fps = value;
      else
        o.timeout_s = v;
    }
  }
  if (i >= args.size()) {
    std::fprintf(stderr, "glbudget: calibrate --app: no app to run (put it after --)\n%s", kUsage);
    return std::nullopt;
  }
  o.app.assign(args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
  o.app.push_back(nullptr);
  if (o.manifest.empty()) o.manifest = manifest::default_manifest_path(fs::path(o.app[0]).filename().string());
  if (o.manifest.empty()) {
    std::fprintf(stderr,
                 "glbudget: calibrate --app: no manifest for %s (pass --config, set GLBUDGET_CONFIG, or put it in "
                 "$XDG_CONFIG_HOME/glbudget/%s.toml): only a manifest's levels have costs to measure\n",
                 o.app[0], fs::path(o.app[0]).filename().c_str());
    return std::nullopt;
  }
  return o;
}

// The highest frame number in the shim's log so far (read from `offset` on; whole lines only).
class LogFollower {
 public:
  explicit LogFollower(std::string path) : path_(std::move(path)) {}
  std::uint64_t frames() {
    std::ifstream in(path_, std::ios::binary);
    if (!in) return highest_;
    in.seekg(static_cast<std::streamoff>(offset_));
    std::string chunk((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t last = chunk.rfind('\n');
    if (last == std::string::npos) return highest_;
    std::istringstream lines(chunk.substr(0, last + 1));
    for (std::string line; std::getline(lines, line);) {
      char* end = nullptr;
      const unsigned long long frame = std::strtoull(line.c_str(), &end, 10);
      if (end != line.c_str() && *end == ',') highest_ = std::max<std::uint64_t>(highest_, frame);
    }
    offset_ += last + 1;
    return highest_;
  }

 private:
  std::string path_;
  std::uint64_t offset_ = 0, highest_ = 0;
};

struct RunResult {
  bool started = false;
  bool stopped = false;  // by us, once every level had drawn (or at the timeout)
  bool timed_out = false;
  int status = 0;  // waitpid's
  std::uint64_t frames = 0;
};

RunResult run_app(const Options& o, const std::vector<std::pair<std::string, std::string>>& env, const std::string& log,
                  std::uint64_t frames_needed) {
  RunResult r;
  const pid_t child = fork();
  if (child < 0) {
    std::fprintf(stderr, "glbudget: calibrate --app: fork: %s\n", std::strerror(errno));
    return r;
  }
  if (child == 0) {
    for (const char* name : {"GLBUDGET_POWER", "GLBUDGET_ERROR", "GLBUDGET_PROBE_PERIOD", "GLBUDGET_PROBE_LEVELS",
                             "GLBUDGET_INSTRUMENT", "GLBUDGET_DUMP_PROBES", "GLBUDGET_FPS"})
      unsetenv(name);
    for (const auto& [name, value] : env) setenv(name.c_str(), value.c_str(), 1);
    execvp(o.app[0], o.app.data());
    std::fprintf(stderr, "glbudget: calibrate --app: cannot run %s: %s\n", o.app[0], std::strerror(errno));
    _exit(127);
  }
  r.started = true;
  LogFollower follower(log);
  const auto start = std::chrono::steady_clock::now();
  std::optional<std::chrono::steady_clock::time_point> asked_to_stop;
  for (;;) {
    const pid_t done = waitpid(child, &r.status, WNOHANG);
    if (done == child) break;
    if (done < 0 && errno != EINTR) break;
    r.frames = follower.frames();
    const auto now = std::chrono::steady_clock::now();
    const double elapsed = std::chrono::duration<double>(now - start).count();
    if (!asked_to_stop && (r.frames >= frames_needed || elapsed >= o.timeout_s)) {
      r.stopped = true;
      r.timed_out = r.frames < frames_needed;
      kill(child, SIGTERM);
      asked_to_stop = now;
    } else if (asked_to_stop && std::chrono::duration<double>(now - *asked_to_stop).count() > 5.0) {
      kill(child, SIGKILL);  // it did not stop on SIGTERM
      asked_to_stop = now + std::chrono::hours(1);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  r.frames = std::max(r.frames, follower.frames());
  return r;
}

std::optional<json> read_json(const fs::path& path) {
  std::ifstream in(path);
  if (!in) return std::nullopt;
  json j = json::parse(in, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) return std::nullopt;
  return j;
}

// Invocation-weighted sums of one level's programs.
struct LevelSums {
  double vertex_invocations = 0, vertex_instructions = 0;
  double fragment_invocations = 0, fragment_instructions = 0, fragment_texels = 0;
};

void add_program(const json& program, LevelSums& s) {
  const auto stages = program.find("stages");
  if (stages == program.end() || !stages->is_array()) return;
  for (const json& stage : *stages) {
    const auto m = stage.find("measured");
    if (m == stage.end() || !m->is_object()) continue;
    const double n = m->value("invocations", 0.0);
    const double ins = m->value("instructions_per_invocation", 0.0);
    const double tex = m->value("texel_accesses_per_invocation", 0.0);
    if (!(n > 0) || !std::isfinite(ins) || !std::isfinite(tex)) continue;
    const std::string name = stage.value("stage", "");
    if (name == "vertex") {
      s.vertex_invocations += n;
      s.vertex_instructions += n * ins;
    } else if (name == "fragment") {
      s.fragment_invocations += n;
      s.fragment_instructions += n * ins;
      s.fragment_texels += n * tex;
    }
  }
}

struct PowerRunPlan {
  std::vector<std::string> sequence;  // GLBUDGET_FORCE's configurations, one block each, in rounds
  unsigned block_frames = 0;          // GLBUDGET_FORCE_EVERY
  unsigned rounds = 0;                // times each configuration is measured
};

// Frames measured per configuration in a round (the first two of each block are left out,
// settled_samples), and the most rounds: GLBUDGET_FORCE lists every block, and one environment
// string holds at most 128 KiB.
constexpr unsigned kMeasuredPerRound = 3;
constexpr unsigned kMostRounds = 64;

// GLBUDGET_FORCE for the power run: level 0 everywhere, then each level of each pass alone, so
// that each level's power is told apart from every other's, then the cheapest configuration
// (every pass at its last level). The best and the cheapest are the range a share of it is taken
// over (the governor's calibrated_range).
// All of them in short blocks, round after round. The cpu estimate on the demo jumps between
// levels 2-5 W apart for tens of frames at a time: with two blocks of 11 frames per
// configuration, a block that fell in a high stretch moved a level's difference from the best
// by as much as the level saves, and 73 of 216 levels measured over 18 of the evaluations'
// calibrations drew more than the best (up to 4.6 W), so that the levels' summed changes put
// the cheapest anywhere from 0.5 to 33 W under the best. Short blocks spread each
// configuration's frames over the whole run, so such a stretch falls on every configuration
// about alike. Each round of the first half starts further along the list, so that no
// configuration's blocks of two rounds run into one (the best measured in fewer, longer
// blocks would carry a high stretch into every level's difference); the second half is the
// first's mirror image, so that each configuration's frames are centred on the run and a drift
// linear in time, of the sensor or of the scene along the app's camera path, cancels from every
// configuration's mean and from each level's difference from the best.
PowerRunPlan power_run_plan(const manifest::Manifest& m, unsigned power_frames) {
  const std::string best = best_configuration(m);
  std::string cheapest;
  for (std::size_t i = 0; i < m.passes.size(); ++i)
    cheapest += (i ? "," : "") + std::to_string(m.passes[i].levels.empty() ? 0 : m.passes[i].levels.size() - 1);
  std::vector<std::string> forward{best};
  for (std::size_t i = 0; i < m.passes.size(); ++i)
    for (std::size_t l = 1; l < m.passes[i].levels.size(); ++l) {
      std::string c;
      for (std::size_t j = 0; j < m.passes.size(); ++j) c += (j ? "," : "") + std::to_string(j == i ? l : 0);
      forward.push_back(c);
    }
  if (std::find(forward.begin(), forward.end(), cheapest) == forward.end()) forward.push_back(cheapest);
  PowerRunPlan plan;
  // About power_frames - 2 frames measured per configuration, about kMeasuredPerRound a round,
  // in an even number of rounds. Under 3, nothing past each switch's first two frames is
  // measured (the command says so).
  const unsigned measured = power_frames < 3 ? 0 : power_frames - 2;
  const unsigned half = std::clamp((measured + kMeasuredPerRound) / (2 * kMeasuredPerRound), 1u, kMostRounds / 2);
  plan.rounds = 2 * half;
  plan.block_frames = power_frames < 3 ? power_frames : 2 + std::max(1u, (measured + plan.rounds - 1) / plan.rounds);
  const std::size_t n = forward.size();
  // A step that never brings a round's first configuration next to the last one's last.
  std::size_t step = std::max<std::size_t>(1, n / half);
  if (n > 2 && step % n == n - 1) step = 1;
  std::vector<std::string> first_half;
  for (unsigned r = 0; r < half; ++r)
    for (std::size_t k = 0; k < n; ++k) first_half.push_back(forward[(r * step + k) % n]);
  plan.sequence = first_half;
  plan.sequence.insert(plan.sequence.end(), first_half.rbegin(), first_half.rend());
  return plan;
}

// The power run's frames as the model sees them, up to its plan's last (GLBUDGET_FORCE starts
// over after it: frames past it would tip the last block's symmetry), leaving out the first two
// of each configuration (their power partly belongs to the one before).
std::vector<model::ConfiguredSample> settled_samples(const analysis::FrameLog& log, const model::VariantTable& table,
                                                     std::uint64_t last_frame) {
  model::PassNames names(table.space);
  std::vector<analysis::LoggedFrame> frames = analysis::frames_of_busiest_context(log);
  std::erase_if(frames, [&](const analysis::LoggedFrame& f) { return f.frame > last_frame; });
  const std::vector<model::ConfiguredSample> all = analysis::configured_samples(frames, table, names);
  std::vector<model::ConfiguredSample> settled;
  for (std::size_t i = 2; i < all.size(); ++i)
    if (all[i].configuration == all[i - 1].configuration && all[i].configuration == all[i - 2].configuration)
      settled.push_back(all[i]);
  return settled;
}

// Runs the app once more, uninstrumented, one level at a time with the power sensor, and fits
// what a batch, vertex, fragment, instruction and texel cost in its frames. Adds
// "platform_costs" and "power" to `table`; false (after saying why) when it cannot.
bool measure_power(const Options& o, const manifest::Manifest& m,
                   const std::vector<std::pair<std::string, std::string>>& base_env, const std::string& scratch,
                   ordered_json& table) {
  std::string profile_path = o.profile;
  if (profile_path.empty()) profile_path = default_profile(o.sensor);
  std::error_code ec;
  if (profile_path.empty() || !fs::is_regular_file(profile_path, ec)) {
    std::fprintf(stderr,
                 "glbudget: calibrate --app: no platform profile (%s): the levels' power is not measured, the table "
                 "holds their instruction and texel counts only; run `glbudget calibrate` first, or pass --profile\n",
                 profile_path.empty() ? "$XDG_CACHE_HOME/glbudget/<sensor>.json" : profile_path.c_str());
    return false;
  }
  const std::optional<model::PlatformProfile> profile = model::load_platform_profile(profile_path);  // says why
  if (!profile) return false;
  const PowerRunPlan plan = power_run_plan(m, o.power_frames);
  const std::vector<std::string>& configurations = plan.sequence;
  std::string force;
  for (const std::string& c : configurations) force += (force.empty() ? "" : ";") + c;
  const std::string log = (fs::path(scratch) / "power.csv").string();
  std::vector<std::pair<std::string, std::string>> env;
  for (const auto& [name, value] : base_env)
    if (name == "LD_PRELOAD" || name == "GLBUDGET_CONFIG") env.emplace_back(name, value);
  env.emplace_back("GLBUDGET_LOG", log);
  env.emplace_back("GLBUDGET_FORCE", force);
  env.emplace_back("GLBUDGET_FORCE_EVERY", std::to_string(plan.block_frames));
  if (!o.sensor.empty()) env.emplace_back("GLBUDGET_SENSOR", o.sensor);
  if (!o.fps.empty()) env.emplace_back("GLBUDGET_FPS", o.fps);
  const std::uint64_t frames_needed = configurations.size() * plan.block_frames + 2;
  std::printf(
      "measuring the power of %zu configurations (the best, each level alone, the cheapest), %u rounds of one "
      "block of %u frames each, the second half of the rounds the first's mirror image%s%s...\n",
      configurations.size() / std::max(1u, plan.rounds), plan.rounds, plan.block_frames, o.fps.empty() ? "" : " at ",
      o.fps.empty() ? "" : (o.fps + " fps").c_str());
  std::fflush(stdout);
  const RunResult run = run_app(o, env, log, frames_needed);
  if (!run.started) return false;
  const std::optional<model::VariantTable> variants = model::parse_variant_table(table.dump(), "the measured table");
  const std::optional<analysis::FrameLog> frames = analysis::read_frame_log_file(log);
  if (!variants || !frames) return false;
  const std::vector<model::ConfiguredSample> samples =
      settled_samples(*frames, *variants, configurations.size() * plan.block_frames);
  const analysis::CostLog logs[] = {{samples, &variants->space}};
  const std::optional<analysis::PlatformCostsFit> fit = analysis::fit_platform_costs(logs, *profile);
  if (!fit) {
    std::fprintf(stderr,
                 "glbudget: calibrate --app: the power run gave no frame with power and counts (is the "
                 "sensor %s readable here?); the levels' power is not measured\n",
                 o.sensor.empty() ? "auto" : o.sensor.c_str());
    return false;
  }
  // Each configuration's mean measured power, for the user and the record.
  // And the mean place of its frames in the run (0: the first frame measured, 1: the last): the
  // rounds' symmetry about the middle, which the drift's cancelling rests on, made visible.
  struct Measured {
    double watts = 0.0, place = 0.0;
    int frames = 0;
  };
  std::map<model::Configuration, Measured> power;
  const double last_place = samples.size() > 1 ? static_cast<double>(samples.size() - 1) : 1.0;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (const model::ConfiguredSample& s = samples[i]; std::isfinite(s.sample.power_w)) {
      Measured& m = power[s.configuration];
      m.watts += s.sample.power_w;
      m.place += static_cast<double>(i) / last_place;
      ++m.frames;
    }
  ordered_json measured = ordered_json::array();
  std::printf("%-24s %9s %7s\n", "configuration", "power W", "frames");
  std::set<std::string> listed;
  for (const std::string& c : configurations) {
    if (!listed.insert(c).second) continue;  // measured in every round, listed once
    std::string colon = c;
    std::replace(colon.begin(), colon.end(), ',', ':');
    const auto parsed = model::parse_configuration(colon, variants->space);
    const auto it = parsed ? power.find(*parsed) : power.end();
    if (it == power.end()) continue;
    const Measured& m = it->second;
    const double mean = m.watts / m.frames;
    std::printf("%-24s %9.2f %7d\n", colon.c_str(), mean, m.frames);
    measured.push_back(
        {{"configuration", colon}, {"power_w", mean}, {"frames", m.frames}, {"mean_place", m.place / m.frames}});
  }
  if (measured.size() < listed.size())
    std::fprintf(stderr,
                 "glbudget: calibrate --app: the power run measured %zu of its %zu configurations (the app ended, "
                 "or --timeout came, before the rest); the costs are fitted from those\n",
                 measured.size(), listed.size());
  const model::PlatformCosts& k = fit->costs;
  std::printf(
      "costs in this app's frames: batch %.4g, vertex %.4g, fragment %.4g, instruction %.4g, texel %.4g "
      "(in-sample error: %.1f %% per frame, %.1f %% per configuration)\n",
      k.batch, k.vertex, k.fragment, k.instruction, k.texel, fit->per_frame[0].mape_percent(),
      fit->per_configuration[0].mape_percent());
  table["platform_costs"] = {{"batch", k.batch},
                             {"vertex", k.vertex},
                             {"fragment", k.fragment},
                             {"instruction", k.instruction},
                             {"texel", k.texel}};
  table["power"] = {{"profile", fs::absolute(profile_path, ec).string()},
                    {"sensor", o.sensor.empty() ? "auto" : o.sensor},
                    {"fps", o.fps.empty() ? "the app's own" : o.fps},
                    {"frames", fit->samples_used},
                    {"rounds", plan.rounds},
                    {"block_frames", plan.block_frames},
                    {"error_per_frame_percent", fit->per_frame[0].mape_percent()},
                    {"error_per_configuration_percent", fit->per_configuration[0].mape_percent()},
                    {"configurations", std::move(measured)}};
  return true;
}

// Runs the app at its best with probes of every level (calibrate_errors.hpp) and adds each
// level's "error_ratio" to `table`'s passes and an "errors" section; false after saying why.
bool measure_error_ratios(const Options& o, const manifest::Manifest& m,
                          const std::vector<std::pair<std::string, std::string>>& base_env, const std::string& scratch,
                          ordered_json& table) {
  const std::string log = (fs::path(scratch) / "errors.csv").string();
  std::vector<std::pair<std::string, std::string>> env;
  for (const auto& [name, value] : base_env)
    if (name == "LD_PRELOAD" || name == "GLBUDGET_CONFIG") env.emplace_back(name, value);
  env.emplace_back("GLBUDGET_LOG", log);
  env.emplace_back("GLBUDGET_FORCE", best_configuration(m));
  env.emplace_back("GLBUDGET_PROBE_PERIOD", "2");
  env.emplace_back("GLBUDGET_PROBE_LEVELS", "all");
  std::printf("measuring each level's error against the best, %u probe frames per level...\n", o.error_probes);
  std::fflush(stdout);
  const RunResult run = run_app(o, env, log, error_run_frames(m, o.error_probes));
  if (!run.started) return false;
  const std::optional<model::VariantTable> variants = model::parse_variant_table(table.dump(), "the measured table");
  const std::optional<ErrorRatios> errors = variants ? error_ratios_from_log(log, variants->space) : std::nullopt;
  if (!errors) {
    std::fprintf(stderr, "glbudget: calibrate --app: the levels' errors are not measured\n");
    return false;
  }
  if (errors->measured.empty()) {
    std::fprintf(stderr,
                 "glbudget: calibrate --app: no probe frame measured a level's error (the shim probes GL 4.2 / "
                 "GLES 3.1 contexts whose passes draw, and logs each stream's error in probe_streams); the "
                 "governor keeps l / lmax\n");
    return false;
  }
  std::printf("%-16s %5s %10s %7s %7s\n", "pass", "level", "error", "probes", "k");
  ordered_json measured = ordered_json::array();
  for (ordered_json& pass : table["passes"]) {
    const std::string name = pass.value("name", "");
    for (std::size_t l = 1; l < pass["levels"].size(); ++l) {
      const auto level = errors->measured.find({name, static_cast<int>(l)});
      if (level == errors->measured.end()) continue;
      const auto k = errors->ratios.find({name, static_cast<int>(l)});
      if (k != errors->ratios.end()) pass["levels"][l]["error_ratio"] = k->second;
      std::printf("%-16s %5zu %10.5f %7d %7s\n", name.c_str(), l, level->second.mean_error, level->second.probes,
                  k == errors->ratios.end() ? "-" : std::to_string(k->second).substr(0, 5).c_str());
      measured.push_back(
          {{"pass", name}, {"level", l}, {"error", level->second.mean_error}, {"probes", level->second.probes}});
    }
  }
  table["errors"] = {{"probes_per_level", o.error_probes}, {"levels", std::move(measured)}};
  return true;
}

}  // namespace

int calibrate_app_main(std::span<char* const> args) {
  int status = 2;
  const std::optional<Options> o = parse(args, status);
  if (!o) return status;

  manifest::LoadResult loaded = manifest::load_manifest(o->manifest);
  for (const manifest::Problem& p : loaded.problems) std::fprintf(stderr, "glbudget: %s\n", p.text.c_str());
  if (!loaded.manifest) {
    std::fprintf(stderr, "glbudget: calibrate --app: manifest %s cannot be used\n", o->manifest.c_str());
    return 2;
  }
  // The passes as the shim applies them (the built-in render scale first when the manifest has none).
  const manifest::Manifest m = manifest::with_resolution_pass(std::move(loaded.manifest));
  std::size_t levels = 1;
  for (const manifest::Pass& p : m.passes) levels = std::max(levels, p.levels.size());
  std::string force;
  for (std::size_t l = 0; l < levels; ++l) {
    if (l) force += ';';
    for (std::size_t i = 0; i < m.passes.size(); ++i)
      force += (i ? "," : "") + std::to_string(std::min(l, m.passes[i].levels.size() - 1));
  }

  const std::string shim = find_shim();
  if (shim.empty()) {
    std::fprintf(stderr,
                 "glbudget: calibrate --app: libglbudget.so not found beside this program (set GLBUDGET_SHIM)\n");
    return 2;
  }
  std::string scratch = (fs::temp_directory_path() / "glbudget-calibrate-app-XXXXXX").string();
  if (!mkdtemp(scratch.data())) {
    std::fprintf(stderr, "glbudget: calibrate --app: cannot make a scratch directory: %s\n", std::strerror(errno));
    return 2;
  }
  const fs::path dump = fs::path(scratch) / "dump";
  const std::string log = (fs::path(scratch) / "frames.csv").string();
  const std::string preload = preload_with_shim(shim, std::getenv("LD_PRELOAD"));
  std::error_code ec;
  const std::vector<std::pair<std::string, std::string>> env = {
      {"LD_PRELOAD", preload},          {"GLBUDGET_CONFIG", fs::absolute(o->manifest, ec).string()},
      {"GLBUDGET_DUMP", dump.string()}, {"GLBUDGET_LOG", log},
      {"GLBUDGET_FORCE", force},        {"GLBUDGET_FORCE_EVERY", std::to_string(o->frames)}};
  // Every level's frames, then a few more: counters are read back a few frames late.
  const std::uint64_t frames_needed = levels * o->frames + 8;
  std::printf("measuring %zu levels of %zu passes, %u frames each (%s)...\n", levels, m.passes.size(), o->frames,
              o->manifest.c_str());
  std::fflush(stdout);
  const RunResult run = run_app(*o, env, log, frames_needed);
  auto cleanup = [&] { fs::remove_all(scratch, ec); };
  if (!run.started) return cleanup(), 2;
  if (!run.stopped) {
    if (WIFEXITED(run.status) && WEXITSTATUS(run.status) == 127) return cleanup(), 2;
    if (run.frames < frames_needed)
      std::fprintf(stderr,
                   "glbudget: calibrate --app: the app ended after %llu frames (%s %d); levels after frame %llu "
                   "are measured from fewer frames or not at all\n",
                   static_cast<unsigned long long>(run.frames), WIFSIGNALED(run.status) ? "signal" : "exit status",
                   WIFSIGNALED(run.status) ? WTERMSIG(run.status) : WEXITSTATUS(run.status),
                   static_cast<unsigned long long>(levels * o->frames));
  } else if (run.timed_out) {
    std::fprintf(stderr, "glbudget: calibrate --app: stopped at the %.0f-s timeout after %llu frames\n", o->timeout_s,
                 static_cast<unsigned long long>(run.frames));
  }

  const std::optional<json> drawn = read_json(dump / "variants.json");
  if (!drawn || !drawn->contains("passes")) {
    std::fprintf(stderr,
                 "glbudget: calibrate --app: the app linked no program the manifest's passes match (%s), or the "
                 "shim could not instrument in this context (it needs GL 4.3 or GLES 3.1); nothing measured\n",
                 o->manifest.c_str());
    return cleanup(), 1;
  }
  std::map<std::string, json> programs;
  for (const auto& entry : fs::directory_iterator(dump, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("program-", 0) == 0 && entry.path().extension() == ".json")
      if (auto j = read_json(entry.path()); j && j->contains("hash")) programs[j->value("hash", "")] = *j;
  }

  ordered_json out_passes = ordered_json::array();
  int measured = 0, unmeasured = 0;
  std::printf("%-16s %5s  %-28s %10s %10s %10s\n", "pass", "level", "name", "ins/vertex", "ins/frag", "texels/frag");
  for (const json& pass : (*drawn)["passes"]) {
    const std::string pass_name = pass.value("name", "");
    ordered_json out_levels = ordered_json::array();
    std::optional<LevelSums> previous;  // the nearest measured level above, for levels that drew nothing
    for (const json& level : pass.value("levels", json::array())) {
      const std::string level_name = level.value("name", "");
      ordered_json out{{"name", level_name}};
      if (level.contains("hashes")) out["hashes"] = level["hashes"];
      const bool draws = level.value("draws", true);
      LevelSums sums;
      for (const json& name : level.value("programs", json::array()))
        if (auto it = programs.find(name.get<std::string>()); it != programs.end()) add_program(it->second, sums);
      const bool has_programs = level.contains("programs");
      const bool drew = sums.fragment_invocations > 0 || sums.vertex_invocations > 0;
      if (drew) previous = sums;
      const LevelSums& used = drew || !previous ? sums : *previous;
      const double ins_v = used.vertex_invocations > 0 ? used.vertex_instructions / used.vertex_invocations : 0.0;
      const double ins_f = used.fragment_invocations > 0 ? used.fragment_instructions / used.fragment_invocations : 0.0;
      const double tex_f = used.fragment_invocations > 0 ? used.fragment_texels / used.fragment_invocations : 0.0;
      if (has_programs && draws) {
        out["ins_v"] = ins_v;
        out["ins_f"] = ins_f;
        out["tex_f"] = tex_f;
        out["measured"] = drew;
        drew ? ++measured : ++unmeasured;
      }
      if (level.contains("fragment_scale")) out["fragment_scale"] = level["fragment_scale"];
      if (!draws) out["draws"] = false;
      if (!has_programs) {
        std::printf("%-16s %5zu  %-28.28s %10s %10s %10s\n", pass_name.c_str(), out_levels.size(), level_name.c_str(),
                    "-", "-", "-");
      } else if (!draws) {
        std::printf("%-16s %5zu  %-28.28s %32s\n", pass_name.c_str(), out_levels.size(), level_name.c_str(),
                    "skips the pass");
      } else {
        std::printf("%-16s %5zu  %-28.28s %10.1f %10.1f %10.2f%s\n", pass_name.c_str(), out_levels.size(),
                    level_name.c_str(), ins_v, ins_f, tex_f, drew ? "" : "  (not drawn: the level above's)");
      }
      out_levels.push_back(std::move(out));
    }
    ordered_json p{{"name", pass_name}};
    if (pass.contains("scales")) p["scales"] = pass["scales"];
    p["levels"] = std::move(out_levels);
    out_passes.push_back(std::move(p));
  }
  const std::string executable = drawn->value("executable", fs::path(o->app[0]).filename().string());
  ordered_json table{{"executable", executable},
                     {"manifest", fs::absolute(o->manifest, ec).string()},
                     {"frames_per_level", o->frames},
                     {"passes", std::move(out_passes)}};
  if (measured == 0) {
    std::fprintf(stderr, "glbudget: calibrate --app: no level's programs drew while measured; nothing written\n");
    return cleanup(), 1;
  }
  if (o->power_frames > 0) measure_power(*o, m, env, scratch, table);
  if (o->error_probes > 0) measure_error_ratios(*o, m, env, scratch, table);
  cleanup();
  if (unmeasured)
    std::fprintf(stderr,
                 "glbudget: calibrate --app: %d level(s) drew nothing while measured (the app may draw those "
                 "passes only in some scenes); they are given the level above's costs\n",
                 unmeasured);

  std::string output = o->output;
  if (output.empty()) output = sensors::default_variant_table_path(executable);
  if (output.empty()) {
    std::fprintf(
        stderr,
        "glbudget: calibrate --app: nowhere to write the table: set XDG_CACHE_HOME or HOME, or pass --output\n");
    return 2;
  }
  if (fs::path(output).has_parent_path()) fs::create_directories(fs::path(output).parent_path(), ec);
  const std::string temporary = output + ".tmp";
  {
    std::ofstream out(temporary, std::ios::trunc);
    out << table.dump(1) << "\n";
    if (!out.flush()) {
      std::fprintf(stderr, "glbudget: calibrate --app: cannot write %s\n", temporary.c_str());
      return 2;
    }
  }
  fs::rename(temporary, output, ec);
  if (ec) {
    std::fprintf(stderr, "glbudget: calibrate --app: cannot write %s: %s\n", output.c_str(), ec.message().c_str());
    return 2;
  }
  std::printf("wrote %s (%d levels measured over %llu frames)\n", output.c_str(), measured,
              static_cast<unsigned long long>(run.frames));
  return 0;
}

}  // namespace glbudget::cli
