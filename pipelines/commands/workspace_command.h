#ifndef SOFTBENCH_PIPELINES_COMMANDS_WORKSPACE_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_WORKSPACE_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

#include "pipelines/commands/model_selection.h"

namespace softbench {

// `softbench workspace`: every combination of pressure levels 0, step, ...,
// max (thesis figs. 4.6 and 4.12), written as a predictions CSV, with the
// extents per head printed.
struct WorkspaceCommandOptions {
  ModelSelection model;
  double max_pressure = 6.0;  // in the selected unit
  double step = 1.0;          // in the selected unit
  int threads = 0;            // 0: all hardware threads
  std::string output_path;    // optional CSV ("-": standard output)
};

// Adds the command's flags to `command`, bound to `options`.
void AddWorkspaceCommand(CLI::App* command, WorkspaceCommandOptions* options);
int RunWorkspace(const WorkspaceCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_WORKSPACE_COMMAND_H_
