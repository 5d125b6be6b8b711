#include "load_runner.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include "shim_path.hpp"

extern char** environ;

namespace glbudget::cli {

namespace {

volatile sig_atomic_t g_interrupted = 0;
volatile pid_t g_load = 0;

void on_interrupt(int) {
  g_interrupted = 1;
  // A Ctrl-C reaches the whole process group; a kill reaches only us.
  if (g_load > 0) kill(g_load, SIGINT);
}

// Settings that would make the shim govern, pace or instrument the load instead of observing it.
constexpr const char* kCleared[] = {"GLBUDGET_POWER",       "GLBUDGET_ERROR", "GLBUDGET_CONFIG", "GLBUDGET_FORCE",
                                    "GLBUDGET_FORCE_EVERY", "GLBUDGET_FPS",   "GLBUDGET_DUMP",   "GLBUDGET_INSTRUMENT",
                                    "GLBUDGET_PROFILE",     "GLBUDGET_LOG",   "GLBUDGET_SENSOR", "LD_PRELOAD"};

bool cleared(std::string_view entry) {
  for (std::string_view name : kCleared)
    if (entry.size() > name.size() && entry.substr(0, name.size()) == name && entry[name.size()] == '=') return true;
  return false;
}

bool parse_step(const std::string& line, LoadStep& step) {
  std::istringstream in(line);
  std::string word;
  if (!(in >> word) || word != "step") return false;
  long long index = 0;
  in >> index;
  int fields = 0;
  while (in >> word) {
    if (word == "interrupted") {
      step.interrupted = true;
      continue;
    }
    long long value = 0;
    if (!(in >> value)) return false;
    if (word == "batches")
      step.batches = static_cast<double>(value);
    else if (word == "vertices")
      step.vertices = static_cast<double>(value);
    else if (word == "fragments")
      step.fragments = static_cast<double>(value);
    else if (word == "start_ns")
      step.start_ns = value;
    else if (word == "end_ns")
      step.end_ns = value;
    else if (word == "frames")
      step.frames = value;
    else if (word == "late")
      step.late = value != 0;
    else
      continue;
    ++fields;
  }
  return fields == 7;
}

std::string last_line_of(const std::string& path) {
  std::ifstream in(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace

void catch_interrupts() {
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = 0;  // no SA_RESTART: a blocked read returns, and the loop sees the flag
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

bool interrupted() { return g_interrupted != 0; }

LoadRunner::LoadRunner(std::string load, std::string shim, std::string sensor, std::string work_dir)
    : load_(std::move(load)), shim_(std::move(shim)), sensor_(std::move(sensor)), work_dir_(std::move(work_dir)) {}

std::vector<std::string> LoadRunner::environment(const std::string& log) const {
  std::vector<std::string> env;
  for (char** e = environ; e && *e; ++e)
    if (!cleared(*e)) env.emplace_back(*e);
  env.push_back("LD_PRELOAD=" + preload_with_shim(shim_, nullptr));
  env.push_back("GLBUDGET_LOG=" + log);
  env.push_back("GLBUDGET_SENSOR=" + sensor_);
  env.push_back("GLBUDGET_INSTRUMENT=0");
  return env;
}

LoadRun LoadRunner::run(const std::vector<std::string>& args, const std::function<void(const LoadStep&)>& on_step) {
  LoadRun result;
  const std::string stem = work_dir_ + "/load-" + std::to_string(++runs_);
  const std::string log = stem + ".csv", errors = stem + ".stderr";
  std::vector<std::string> env = environment(log);
  std::vector<char*> argv{const_cast<char*>(load_.c_str())}, envp;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);

  int out[2];
  if (pipe2(out, O_CLOEXEC) != 0) {
    result.failed = true;
    result.failure = std::string("pipe: ") + std::strerror(errno);
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, out[1], STDOUT_FILENO);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, errors.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
  pid_t pid = 0;
  const int spawned = posix_spawn(&pid, load_.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  close(out[1]);
  if (spawned != 0) {
    close(out[0]);
    result.failed = true;
    result.failure = "cannot run " + load_ + ": " + std::strerror(spawned);
    return result;
  }
  g_load = pid;
  if (g_interrupted) kill(pid, SIGINT);  // arrived while we were starting it

  std::string pending;
  char buffer[4096];
  for (;;) {
    const ssize_t n = read(out[0], buffer, sizeof buffer);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    pending.append(buffer, static_cast<std::size_t>(n));
    for (std::size_t eol; (eol = pending.find('\n')) != std::string::npos;) {
      LoadStep step;
      if (parse_step(pending.substr(0, eol), step)) {
        result.steps.push_back(step);
        if (on_step) on_step(step);
      }
      pending.erase(0, eol + 1);
    }
  }
  close(out[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  g_load = 0;
  const bool stopped_by_us = g_interrupted && WIFSIGNALED(status) && WTERMSIG(status) == SIGINT;
  if (!stopped_by_us && (!WIFEXITED(status) || WEXITSTATUS(status) != 0)) {
    result.failed = true;
    const std::string said = last_line_of(errors);
    result.failure = load_ + (WIFEXITED(status) ? " exited with status " + std::to_string(WEXITSTATUS(status))
                                                : " died of signal " + std::to_string(WTERMSIG(status)));
    if (!said.empty()) result.failure += ": " + said;
    return result;
  }
  if (auto frame_log = analysis::read_frame_log_file(log)) result.frames = std::move(frame_log->frames);
  return result;
}

}  // namespace glbudget::cli
