#ifndef SOFTBENCH_PIPELINES_COMMANDS_FIT_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_FIT_COMMAND_H_

#include <CLI/CLI.hpp>
#include <cstdint>
#include <ostream>
#include <string>

#include "pipelines/characterisation/fit_analysis.h"

namespace softbench {

// `softbench fit`: the actuator constants from force-sensor logs (thesis
// chapter 3, Algorithm 1), every variant and the baseline, with goodness of
// fit, a constants file and a report.
struct FitCommandOptions {
  std::string input_path;        // manifest (.yaml) or combined log (.csv)
  std::string output_path;       // constants YAML of `variant`
  std::string report_directory;  // optional
  std::string variant = "small-angle";
  std::string loss = "none";  // none, huber, cauchy
  double loss_scale_n = 1.0;
  double axial_weight = 1.0;
  double shear_weight = 1.0;
  // Rows kept in memory for a robust fit (evenly spaced over the logs).
  int64_t robust_rows = 1000000;
  double natural_length_mm = 18.5;  // L0 of the variable-arm variant
  // For a combined CSV without a manifest.
  // A combined CSV's pressure unit; unset: its pressure_UNIT column says.
  std::optional<std::string> pressure_unit;
  std::string axial = "+fz_n";
  std::string shear = "+fy_n";
  int threads = 0;
  bool decimal_comma = false;  // the logs write 6,5 (declared, not guessed)
  bool quiet = false;
};

// Adds the command's flags to `command`, bound to `options`.
void AddFitCommand(CLI::App* command, FitCommandOptions* options);
// The analysis the flags ask for; throws InputError naming a bad flag.
FitAnalysisOptions FitAnalysisOptionsFromFlags(const FitCommandOptions& flags);
int RunFit(const FitCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_FIT_COMMAND_H_
