#pragma once
// The glbudget command's subcommands. Each lives in its own file and is listed once in
// command_table.cpp.
#include <span>
#include <string_view>

namespace glbudget::cli {

// args: the words after the subcommand's name. Returns the process exit status.
using CommandMain = int (*)(std::span<char* const> args);

struct Command {
  std::string_view name;
  std::string_view summary;  // one line for `glbudget help`
  CommandMain run;
};

std::span<const Command> commands();

}  // namespace glbudget::cli
