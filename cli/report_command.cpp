// glbudget report LOG.csv [--html OUT.html] [--png DIR] [--names a,b,c] [--at FRAME]: draws a
// governed run from the shim's frame log. The drawing is Python with matplotlib
// (cli/report/glbudget_report.py); this finds the script and an interpreter that has
// matplotlib, runs it with the arguments as given and passes its exit status on.
#include <spawn.h>
#include <sys/wait.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

extern char** environ;

namespace glbudget::cli {

namespace {

namespace fs = std::filesystem;

// The script's own exit status when the interpreter lacks matplotlib (and
// GLBUDGET_REPORT_LAUNCHER is set): the next interpreter is tried.
constexpr int kNoMatplotlib = 3;
constexpr int kNotFound = -1;

// Installed: bin/../share/glbudget/; the build tree: the source file itself.
std::string find_script() {
  std::error_code ec;
  std::vector<fs::path> candidates;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (!ec) candidates.push_back(self.parent_path() / "../share/glbudget/glbudget_report.py");
#ifdef GLBUDGET_REPORT_SCRIPT
  candidates.emplace_back(GLBUDGET_REPORT_SCRIPT);
#endif
  for (const fs::path& p : candidates)
    if (fs::is_regular_file(p, ec)) return fs::weakly_canonical(p, ec).string();
  return {};
}

// $GLBUDGET_PYTHON alone when set; else python3 on PATH, then Debian's (a pyenv or venv
// python3 first on PATH often lacks matplotlib).
std::vector<std::string> interpreters() {
  if (const char* env = std::getenv("GLBUDGET_PYTHON"); env && *env) return {env};
  return {"python3", "/usr/bin/python3"};
}

// The script's exit status under `python`; kNotFound when python cannot be started,
// kNoMatplotlib when it has no matplotlib, 128 + N when killed by signal N.
int run_script(const std::string& python, const std::string& script, std::span<char* const> args) {
  std::vector<char*> argv = {const_cast<char*>(python.c_str()), const_cast<char*>(script.c_str())};
  argv.insert(argv.end(), args.begin(), args.end());
  argv.push_back(nullptr);
  pid_t child = 0;
  if (posix_spawnp(&child, python.c_str(), nullptr, nullptr, argv.data(), environ) != 0) return kNotFound;
  int status = 0;
  while (waitpid(child, &status, 0) < 0)
    if (errno != EINTR) return kNotFound;
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  const int code = WEXITSTATUS(status);
  return code == 127 ? kNotFound : code;  // 127: the shell's "cannot execute" for a wrapper script
}

}  // namespace

int report_main(std::span<char* const> args) {
  if (args.empty()) {
    std::fprintf(stderr,
                 "glbudget: report: no log given; usage: glbudget report LOG.csv [--html OUT.html] [--png DIR] "
                 "[--names a,b,c] [--at FRAME]\n");
    return 2;
  }
  const std::string script = find_script();
  if (script.empty()) {
    std::fprintf(stderr, "glbudget: report: cannot find glbudget_report.py (bin/../share/glbudget/ when installed)\n");
    return 2;
  }
  setenv("GLBUDGET_REPORT_LAUNCHER", "1", 1);
  bool started = false;
  for (const std::string& python : interpreters()) {
    const int status = run_script(python, script, args);
    if (status == kNotFound) continue;
    started = true;
    if (status != kNoMatplotlib) return status;
  }
  std::fprintf(stderr,
               started
                   ? "glbudget: report: needs matplotlib for python3 (Debian: apt-get install python3-matplotlib)\n"
                   : "glbudget: report: needs python3 with matplotlib (Debian: apt-get install python3-matplotlib)\n");
  return 2;
}

}  // namespace glbudget::cli
