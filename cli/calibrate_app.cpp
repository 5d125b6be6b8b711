// glbudget calibrate --app: measures what each quality level of an app's manifest costs per
// invocation (executed instructions and texel accesses, per vertex and per fragment), so that
// the power model predicts the saving of levels that change shaders, not only of those that
// change how much is drawn. One run of the app under the shim with instrumentation on and a
// GLBUDGET_FORCE list that draws every pass at level 0, then 1, then 2 ... for N frames each;
// the shim's dump says which program drew each level (variants.json) and what each program
// executed. Writes the variant table (governor/model/variant_table.hpp) the shim reads.
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
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "glbudget/manifest/manifest.hpp"
#include "glbudget/model/variant_table.hpp"
#include "shim_path.hpp"

namespace glbudget::cli {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using nlohmann::ordered_json;

constexpr const char* kUsage =
    "usage: glbudget calibrate --app [--config MANIFEST] [--frames N] [--timeout S] [--output PATH] -- APP [ARGS...]\n";

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
      "(default 600).\n");
}

struct Options {
  std::string manifest, output;
  unsigned frames = 30;
  double timeout_s = 600.0;
  std::vector<char*> app;  // argv, null-terminated
};

std::optional<Options> parse(std::span<char* const> args, int& status) {
  Options o;
  status = 2;
  if (const char* env = std::getenv("GLBUDGET_CONFIG"); env && *env) o.manifest = env;
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
    if (i + 1 >= args.size() || (arg != "--config" && arg != "--frames" && arg != "--timeout" && arg != "--output")) {
      std::fprintf(stderr, "glbudget: calibrate --app: %s %s\n%s", arg.c_str(),
                   i + 1 >= args.size() ? "needs a value" : "is not an option", kUsage);
      return std::nullopt;
    }
    const std::string value = args[++i];
    if (arg == "--config") o.manifest = value;
    else if (arg == "--output") o.output = value;
    else {
      char* end = nullptr;
      const double v = std::strtod(value.c_str(), &end);
      const bool frames = arg == "--frames";
      if (end == value.c_str() || *end || !std::isfinite(v) || (frames ? (v < 1 || v > 100000 || v != std::floor(v)) : v <= 0)) {
        std::fprintf(stderr, "glbudget: calibrate --app: %s %s is not %s\n", arg.c_str(), value.c_str(),
                     frames ? "a number of frames in [1, 100000]" : "a number of seconds > 0");
        return std::nullopt;
      }
      if (frames) o.frames = static_cast<unsigned>(v);
      else o.timeout_s = v;
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
  int status = 0;        // waitpid's
  std::uint64_t frames = 0;
};

RunResult run_app(const Options& o, const std::vector<std::pair<std::string, std::string>>& env,
                  const std::string& log, std::uint64_t frames_needed) {
  RunResult r;
  const pid_t child = fork();
  if (child < 0) {
    std::fprintf(stderr, "glbudget: calibrate --app: fork: %s\n", std::strerror(errno));
    return r;
  }
  if (child == 0) {
    for (const char* name : {"GLBUDGET_POWER", "GLBUDGET_ERROR", "GLBUDGET_PROBE_PERIOD", "GLBUDGET_INSTRUMENT",
                             "GLBUDGET_DUMP_PROBES", "GLBUDGET_FPS"})
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
    std::fprintf(stderr, "glbudget: calibrate --app: libglbudget.so not found beside this program (set GLBUDGET_SHIM)\n");
    return 2;
  }
  std::string scratch = (fs::temp_directory_path() / "glbudget-calibrate-app-XXXXXX").string();
  if (!mkdtemp(scratch.data())) {
    std::fprintf(stderr, "glbudget: calibrate --app: cannot make a scratch directory: %s\n", std::strerror(errno));
    return 2;
  }
  const fs::path dump = fs::path(scratch) / "dump";
  const std::string log = (fs::path(scratch) / "frames.csv").string();
  std::string preload = shim;
  if (const char* old = std::getenv("LD_PRELOAD"); old && *old) preload += std::string(":") + old;
  std::error_code ec;
  const std::vector<std::pair<std::string, std::string>> env = {
      {"LD_PRELOAD", preload},
      {"GLBUDGET_CONFIG", fs::absolute(o->manifest, ec).string()},
      {"GLBUDGET_DUMP", dump.string()},
      {"GLBUDGET_LOG", log},
      {"GLBUDGET_FORCE", force},
      {"GLBUDGET_FORCE_EVERY", std::to_string(o->frames)}};
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
      std::fprintf(stderr, "glbudget: calibrate --app: the app ended after %llu frames (%s %d); levels after frame %llu "
                   "are measured from fewer frames or not at all\n",
                   static_cast<unsigned long long>(run.frames),
                   WIFSIGNALED(run.status) ? "signal" : "exit status",
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
    ordered_json out_levels = ordered_json::array();
    std::optional<LevelSums> previous;  // the nearest measured level above, for levels that drew nothing
    for (const json& level : pass.value("levels", json::array())) {
      ordered_json out{{"name", level.value("name", "")}};
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
      const std::string name = pass.value("name", "") ;
      if (!has_programs) {
        std::printf("%-16s %5zu  %-28.28s %10s %10s %10s\n", name.c_str(), out_levels.size(),
                    out["name"].get<std::string>().c_str(), "-", "-", "-");
      } else if (!draws) {
        std::printf("%-16s %5zu  %-28.28s %32s\n", name.c_str(), out_levels.size(),
                    out["name"].get<std::string>().c_str(), "skips the pass");
      } else {
        std::printf("%-16s %5zu  %-28.28s %10.1f %10.1f %10.2f%s\n", name.c_str(), out_levels.size(),
                    out["name"].get<std::string>().c_str(), ins_v, ins_f, tex_f,
                    drew ? "" : "  (not drawn: the level above's)");
      }
      out_levels.push_back(std::move(out));
    }
    ordered_json p{{"name", pass.value("name", "")}};
    if (pass.contains("scales")) p["scales"] = pass["scales"];
    p["levels"] = std::move(out_levels);
    out_passes.push_back(std::move(p));
  }
  const std::string executable = drawn->value("executable", fs::path(o->app[0]).filename().string());
  ordered_json table{{"executable", executable},
                     {"manifest", fs::absolute(o->manifest, ec).string()},
                     {"frames_per_level", o->frames},
                     {"passes", std::move(out_passes)}};
  cleanup();
  if (measured == 0) {
    std::fprintf(stderr, "glbudget: calibrate --app: no level's programs drew while measured; nothing written\n");
    return 1;
  }
  if (unmeasured)
    std::fprintf(stderr, "glbudget: calibrate --app: %d level(s) drew nothing while measured (the app may draw those "
                 "passes only in some scenes); they are given the level above's costs\n", unmeasured);

  std::string output = o->output;
  if (output.empty()) output = model::default_variant_table_path(executable);
  if (output.empty()) {
    std::fprintf(stderr, "glbudget: calibrate --app: nowhere to write the table: set XDG_CACHE_HOME or HOME, or pass --output\n");
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
