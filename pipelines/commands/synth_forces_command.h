#ifndef SOFTBENCH_PIPELINES_COMMANDS_SYNTH_FORCES_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_SYNTH_FORCES_COMMAND_H_

#include <CLI/CLI.hpp>
#include <optional>
#include <ostream>
#include <string>

#include "calibration/synthetic_force_log.h"

namespace softbench {

// `softbench synth-forces`: the thesis's 54-test characterisation protocol
// as force-sensor logs from known constants (one CSV per test and a
// manifest, or one combined CSV), for `softbench fit` and its benchmark.
struct SynthForcesCommandOptions {
  std::string output_directory;
  std::string constants_path;          // empty: the thesis's constants
  std::optional<std::string> variant;  // unset: the constants file's
  std::string pressure_unit = "kpa";
  bool combined = false;     // one CSV with configuration columns
  bool noise_only = false;   // switch off every imperfection but noise
  std::string hysteresis_n;  // "axial,shear" added on the way down
  int threads = 0;           // 0: all cores
  bool quiet = false;
  SyntheticForceLogOptions synthetic;
};

// Adds the command's flags to `command`, bound to `options`.
void AddSynthForcesCommand(CLI::App* command,
                           SynthForcesCommandOptions* options);
int RunSynthForces(SynthForcesCommandOptions options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_SYNTH_FORCES_COMMAND_H_
