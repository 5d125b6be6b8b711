// glbudget run [options] -- APP [ARGS...]: runs an unmodified GL app under the shim. Sets up
// LD_PRELOAD and the GLBUDGET_* variables from the options, finds the platform profile (or
// says how to make one), and passes the app's exit status and the signals sent to it through.
#include <signal.h>
#include <sys/wait.h>
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
      "status is APP's; signals sent to glbudget reach APP.\n");
}

pid_t g_child = 0;
void forward(int sig) {
  if (g_child > 0) kill(g_child, sig);
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
  // Signals sent to us (Ctrl-C reaches the whole process group anyway; kill does not) go to
  // the app; we wait for it and exit as it did.
  struct sigaction sa {};
  sa.sa_handler = forward;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2}) sigaction(sig, &sa, nullptr);
  g_child = fork();
  if (g_child < 0) {
    std::fprintf(stderr, "glbudget: run: fork: %s\n", std::strerror(errno));
    return 2;
  }
  if (g_child == 0) {
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2}) sigaction(sig, &dfl, nullptr);
    execvp(argv[0], argv.data());
    std::fprintf(stderr, "glbudget: run: cannot run %s: %s\n", argv[0], std::strerror(errno));
    _exit(127);
  }
  int status = 0;
  while (waitpid(g_child, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) {
    // Die of the same signal, so whoever runs us sees what the app saw.
    const int sig = WTERMSIG(status);
    struct sigaction dfl {};
    dfl.sa_handler = SIG_DFL;
    sigaction(sig, &dfl, nullptr);
    kill(getpid(), sig);
    return 128 + sig;
  }
  return 1;
}

}  // namespace glbudget::cli
