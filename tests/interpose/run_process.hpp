// Runs a program with extra environment variables and captures what it printed.
#pragma once
#include <map>
#include <string>
#include <vector>

struct ProcessResult {
  int exit_code = -1;  // exit status, or 128 + signal number
  std::string out, err;
};

// An env map's LD_PRELOAD is given to the process as preload_value(its value).
ProcessResult run_process(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env);

// What LD_PRELOAD must hold to preload `shim`: in a sanitizer build (GLBUDGET_SANITIZED_SHIM)
// the sanitizer's runtime ahead of it, since the host is not linked with it; else the shim.
std::string preload_value(const std::string& shim);

// The same, started and left running: its stdin is /dev/null, stdout and stderr go to the
// files named (created or truncated). Returns its pid, or -1. wait_process() reaps it and
// returns its exit status, or 128 + signal number.
int spawn_process(const std::vector<std::string>& argv, const std::map<std::string, std::string>& env,
                  const std::string& out_path, const std::string& err_path);
int wait_process(int pid);

std::string read_file(const std::string& path);
// How many lines of text contain needle.
size_t count_lines_with(const std::string& text, const std::string& needle);
bool file_exists(const std::string& path);

// A CSV file as rows of fields; the header is row 0.
std::vector<std::vector<std::string>> read_csv(const std::string& path);
// The data rows of a CSV file, each field by its header's name; a short row has fewer fields.
std::vector<std::map<std::string, std::string>> read_csv_rows_by_name(const std::string& path);
