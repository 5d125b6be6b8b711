// glbudget run [options] -- APP [ARGS...]: runs an unmodified GL app under the shim. Sets up
// LD_PRELOAD and the GLBUDGET_* variables from the options, finds the platform profile (or
// says how to make one), and passes the app's exit status and the signals sent to it through.
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "command.hpp"
#include "glbudget/model/selection.hpp"
#include "shim_path.hpp"

namespace glbudget::cli {

namespace {

namespace fs = std::filesystem;

void print_help() {
  std::printf(
      "usage: glbudget run [--power P%%|W] [--error E] [--fps N] [--config MANIFEST.toml]\n"
      "                    [--force LEVELS] [--log RUN.csv] [--sensor S] [--profile P.json] -- APP [ARGS...]\n\n"
      "Runs APP with the glbudget shim preloaded. --power keeps it under a budget: a share of the\n"
      "range between the scene's lowest and highest predicted power (40%%), or watts (35W).\n"
      "--error E: the lowest power whose estimated error (1 - SSIM) stays under E. --fps paces\n"
      "frames (power is only saved when the GPU idles between them). --config names the\n"
      "variant manifest (default $XDG_CONFIG_HOME/glbudget/<exe>.toml). --force draws one\n"
      "configuration (a level per manifest pass). --log writes the per-frame CSV. The exit\n"
      "status is APP's: glbudget runs it in its own place, so the signals sent to it reach APP.\n");
}

}  // namespace

int run_main(std::span<char* const> args) {
  std::vector<std::pair<std::string, std::string>> env;
  std::string sensor, profile;
  bool budget = false;
  std::size_t i = 0;
  auto value = [&](const char* option) -> const char* {
    if (i + 1 >= args.size()) {
      std::fprintf(stderr, "glbudget: run: %s needs a value\n", option);
      return nullptr;
    }
    return args[++i];
  };
  for (; i < args.size(); ++i) {
    const std::string arg = args[i];
    if (arg == "--") {
      ++i;
      break;
    }
    if (arg == "--help" || arg == "-h") {
      print_help();
      return 0;
    }
    const char* v = nullptr;
    if (arg == "--power") {
      if (!(v = value("--power"))) return 2;
      if (!model::parse_budget(v)) return 2;  // parse_budget said why
      env.emplace_back("GLBUDGET_POWER", v);
      budget = true;
    } else if (arg == "--error") {
      if (!(v = value("--error"))) return 2;
      if (!model::parse_error_budget(v)) {
        std::fprintf(stderr, "glbudget: run: --error %s is not an error (1 - SSIM) in [0, 1]\n", v);
        return 2;
      }
      env.emplace_back("GLBUDGET_ERROR", v);
      budget = true;
    } else if (arg == "--fps") {
      if (!(v = value("--fps"))) return 2;
      env.emplace_back("GLBUDGET_FPS", v);
    } else if (arg == "--config") {
      if (!(v = value("--config"))) return 2;
      std::error_code ec;
      if (!fs::is_regular_file(v, ec)) {
        std::fprintf(stderr, "glbudget: run: manifest %s does not exist\n", v);
        return 2;
      }
      env.emplace_back("GLBUDGET_CONFIG", fs::absolute(v).string());
    } else if (arg == "--force") {
      if (!(v = value("--force"))) return 2;
      env.emplace_back("GLBUDGET_FORCE", v);
    } else if (arg == "--log") {
      if (!(v = value("--log"))) return 2;
      env.emplace_back("GLBUDGET_LOG", fs::absolute(v).string());
    } else if (arg == "--sensor") {
      if (!(v = value("--sensor"))) return 2;
      sensor = v;
      env.emplace_back("GLBUDGET_SENSOR", v);
    } else if (arg == "--profile") {
      if (!(v = value("--profile"))) return 2;
      profile = fs::absolute(v).string();
    } else if (!arg.empty() && arg[0] == '-') {
      std::fprintf(stderr, "glbudget: run: unknown option %s (see glbudget run --help)\n", arg.c_str());
      return 2;
    } else {
      break;  // the app, without a "--"
    }
  }
  if (i >= args.size()) {
    std::fprintf(stderr, "glbudget: run: no program to run (usage: glbudget run [options] -- APP [ARGS...])\n");
    return 2;
  }
  const std::string shim = find_shim();
  if (shim.empty()) {
    std::fprintf(stderr, "glbudget: run: libglbudget.so not found beside this program (set GLBUDGET_SHIM)\n");
    return 2;
  }
  if (profile.empty()) {
    if (const char* p = std::getenv("GLBUDGET_PROFILE"); p && *p)
      profile = p;
    else
      profile = default_profile(sensor.empty() ? (std::getenv("GLBUDGET_SENSOR") ? std::getenv("GLBUDGET_SENSOR") : "")
                                               : sensor);
  }
  std::error_code ec;
  if (!profile.empty() && fs::is_regular_file(profile, ec)) {
    env.emplace_back("GLBUDGET_PROFILE", profile);
  } else if (budget) {
    std::fprintf(stderr,
                 "glbudget: run: no platform profile for this machine's sensor (looked for %s); the budget "
                 "needs one: run `glbudget calibrate` once, or pass --profile\n",
                 profile.empty() ? "$XDG_CACHE_HOME/glbudget/<sensor>.json" : profile.c_str());
    return 2;
  }

  // LD_PRELOAD: the shim first, anything the user preloads after it.
  setenv("LD_PRELOAD", preload_with_shim(shim, std::getenv("LD_PRELOAD")).c_str(), 1);
  for (const auto& [name, v] : env) setenv(name.c_str(), v.c_str(), 1);

  std::vector<char*> argv(args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
  argv.push_back(nullptr);
  // The app takes our place: its exit status and the signals that reach it are its own. A
  // parent that forwarded signals delivered those sent to the whole process group twice (Ctrl-C,
  // `timeout` without --foreground), and ioquake3 died of its "DOUBLE SIGNAL FAULT".
  execvp(argv[0], argv.data());
  std::fprintf(stderr, "glbudget: run: cannot run %s: %s\n", argv[0], std::strerror(errno));
  return 127;
}

}  // namespace glbudget::cli
