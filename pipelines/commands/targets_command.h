#ifndef SOFTBENCH_PIPELINES_COMMANDS_TARGETS_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_TARGETS_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace softbench {

// `softbench targets`: the sheets a bench needs, print-ready (PDF and SVG):
// the plan's AprilTag at its exact size with check bars and a ruler, the
// calibration checkerboard, and the dot stickers in the plan's colours.
struct TargetsCommandOptions {
  std::string output_dir;
  std::string plan_path;  // tag and dots from the plan; else the flags below
  int tag_id = 0;
  double tag_mm = 50.0;
  std::string dot_colors = "red";
  double dot_mm = 4.0;
  int dots_per_head = 3;
  std::string board = "9x6";
  double square_mm = 20.0;
  std::string paper = "a4";
};

// Adds the command's flags to `command`, bound to `options`.
void AddTargetsCommand(CLI::App* command, TargetsCommandOptions* options);
int RunTargets(const TargetsCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_TARGETS_COMMAND_H_
