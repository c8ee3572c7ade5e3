#ifndef SOFTBENCH_PIPELINES_COMMANDS_COMMAND_TABLE_H_
#define SOFTBENCH_PIPELINES_COMMANDS_COMMAND_TABLE_H_

#include <CLI/CLI.hpp>
#include <functional>
#include <ostream>
#include <span>
#include <string_view>

namespace softbench {

// Flags every command shares (given before the command's name).
struct GlobalFlags {
  bool quiet = false;  // errors only: no progress bars, no warnings
};

// Runs a command whose flags were parsed; returns the exit code.
using CommandRun = std::function<int(const GlobalFlags&, std::ostream& out)>;

// One `softbench` command (in the manner of COLMAP's command table): its
// name, one line of help, and how to add its flags to its CLI11 subcommand,
// which gives the function that runs it with them.
struct Command {
  std::string_view name;
  std::string_view help;
  std::function<CommandRun(CLI::App* command)> add_flags;
};

// Every command, in the order `softbench --help` lists them.
std::span<const Command> Commands();

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_COMMAND_TABLE_H_
