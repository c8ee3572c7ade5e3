#ifndef SOFTBENCH_PIPELINES_COMMANDS_INVERSE_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_INVERSE_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

#include "pipelines/commands/model_selection.h"

namespace softbench {

// `softbench inverse`: the pressures in [0, max] that put the heads at a
// target, or the verdict "unreachable" with the closest reachable point.
struct InverseCommandOptions {
  ModelSelection model;
  std::string target;  // "y,z" per head, in mm
  // Highest allowed pressure in the selected unit; unset: 6 psi, the
  // thesis's regulator limit.
  std::optional<double> max_pressure;
};

// Exit code of an unreachable target (the answer is printed, not an error).
inline constexpr int kExitUnreachable = 3;

// Adds the command's flags to `command`, bound to `options`.
void AddInverseCommand(CLI::App* command, InverseCommandOptions* options);
int RunInverse(const InverseCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_INVERSE_COMMAND_H_
