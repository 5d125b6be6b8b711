#include "run_process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <fstream>
#include <sstream>

extern char** environ;

std::string read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

bool file_exists(const std::string& path) {
  struct stat st;
  return stat(path.c_str(), &st) == 0;
}

std::string preload_value(const std::string& shim) {
#ifdef SANITIZER_PRELOAD
  // The sanitizer's runtime must be loaded before anything it intercepts is called.
  return std::string(SANITIZER_PRELOAD) + ":" + shim;
#else
  return shim;
#endif
}

int spawn_process(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
                  const std::string& out_path, const std::string& err_path) {
  std::vector<std::string> env_strings;
  for (char** e = environ; *e; ++e) {
    std::string s(*e);
    std::string name = s.substr(0, s.find('='));
    if (!env.count(name) && name != "LD_PRELOAD" && name.rfind("GLBUDGET_", 0) != 0) env_strings.push_back(s);
  }
  for (auto& [k, v] : env) env_strings.push_back(k + "=" + (k == "LD_PRELOAD" && !v.empty() ? preload_value(v) : v));
#ifdef SANITIZER_ENV
  // The sanitizer's options for GL hosts (the top CMakeLists.txt says why), unless the test
  // or the user set them. Any report fails the host's exit code, which every test checks.
  const std::string sanitizer_env = SANITIZER_ENV;
  const std::string sanitizer_var = sanitizer_env.substr(0, sanitizer_env.find('='));
  if (!env.count(sanitizer_var) && !getenv(sanitizer_var.c_str())) env_strings.push_back(sanitizer_env);
#endif
  std::vector<char*> envp, args;
  for (auto& s : env_strings) envp.push_back(s.data());
  envp.push_back(nullptr);
  std::vector<std::string> argv_copy = argv;
  for (auto& s : argv_copy) args.push_back(s.data());
  args.push_back(nullptr);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
  pid_t pid = -1;
  if (posix_spawnp(&pid, args[0], &fa, nullptr, args.data(), envp.data()) != 0) pid = -1;
  posix_spawn_file_actions_destroy(&fa);
  return pid;
}

int wait_process(int pid) {
  int status = 0;
  if (pid < 0) return -1;
  pid_t got;
  while ((got = waitpid(pid, &status, 0)) < 0 && errno == EINTR) {
  }
  if (got != pid) return -1;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

ProcessResult run_process(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env) {
  static int counter = 0;
  std::string base = "/tmp/glbudget_test_" + std::to_string(getpid()) + "_" + std::to_string(counter++);
  std::string out_path = base + ".out", err_path = base + ".err";
  ProcessResult r;
  r.exit_code = wait_process(spawn_process(argv, env, out_path, err_path));
  r.out = read_file(out_path);
  r.err = read_file(err_path);
  unlink(out_path.c_str());
  unlink(err_path.c_str());
  return r;
}

size_t count_lines_with(const std::string& text, const std::string& needle) {
  std::istringstream in(text);
  std::string line;
  size_t n = 0;
  while (std::getline(in, line)) n += line.find(needle) != std::string::npos;
  return n;
}

std::vector<std::vector<std::string>> read_csv(const std::string& path) {
  std::vector<std::vector<std::string>> rows;
  std::ifstream f(path);
  std::string line;
  while (std::getline(f, line)) {
    std::vector<std::string> fields;
    size_t start = 0;
    for (;;) {
      size_t comma = line.find(',', start);
      fields.push_back(line.substr(start, comma - start));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    rows.push_back(fields);
  }
  return rows;
}

std::vector<std::map<std::string, std::string>> read_csv_rows_by_name(const std::string& path) {
  auto csv = read_csv(path);
  std::vector<std::map<std::string, std::string>> rows;
  for (size_t i = 1; i < csv.size(); ++i) {
    std::map<std::string, std::string> row;
    for (size_t c = 0; c < csv[0].size() && c < csv[i].size(); ++c) row[csv[0][c]] = csv[i][c];
    rows.push_back(row);
  }
  return rows;
}
