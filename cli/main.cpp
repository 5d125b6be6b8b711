// glbudget: the command-line tool. `glbudget <command> [args...]`; `glbudget help` lists them.
#include <cstdio>
#include <span>
#include <string_view>

#include "command.hpp"

namespace {

void print_usage(std::FILE* out) {
  std::fprintf(out, "usage: glbudget <command> [options]\n\ncommands:\n");
  for (const auto& command : glbudget::cli::commands())
    std::fprintf(out, "  %-10.*s %.*s\n", static_cast<int>(command.name.size()), command.name.data(),
                 static_cast<int>(command.summary.size()), command.summary.data());
  std::fprintf(out, "  %-10s %s\n", "help", "this list; `glbudget <command> --help` for one");
}

}  // namespace

int main(int argc, char** argv) {
  const std::span<char* const> words(argv, static_cast<std::size_t>(argc));
  if (words.size() < 2) {
    print_usage(stderr);
    return 2;
  }
  const std::string_view name = words[1];
  if (name == "help" || name == "--help" || name == "-h") {
    print_usage(stdout);
    return 0;
  }
  for (const auto& command : glbudget::cli::commands())
    if (command.name == name) return command.run(words.subspan(2));
  std::fprintf(stderr, "glbudget: unknown command \"%s\"\n", words[1]);
  print_usage(stderr);
  return 2;
}
