#ifndef SOFTBENCH_PIPELINES_COMMANDS_PREDICT_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_PREDICT_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

#include "pipelines/commands/model_selection.h"

namespace softbench {

// `softbench predict`: equilibrium head positions for listed pressures.
struct PredictOptions {
  ModelSelection model;
  std::string input_path;      // CSV with columns p1..pN
  std::string output_path;     // predictions CSV ("-": standard output)
  std::string pressures;       // "6,6,0": one configuration, printed for people
  bool decimal_comma = false;  // the CSV writes 6,5 (declared, not guessed)
};

// Adds the command's flags to `command`, bound to `options`.
void AddPredictCommand(CLI::App* command, PredictOptions* options);

// Runs the command; returns the exit code. Throws InputError on bad input,
// before anything is written.
int RunPredict(const PredictOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_PREDICT_COMMAND_H_
