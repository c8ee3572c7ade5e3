#ifndef SOFTBENCH_PIPELINES_COMMANDS_VALIDATE_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_VALIDATE_COMMAND_H_

#include <CLI/CLI.hpp>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "pipelines/validation/validate_video.h"

namespace softbench {

// `softbench validate`: a bench video and its test plan in, the thesis's
// per-test-point validation (figs. 4.8, 4.9, 4.16, 4.17) out.
struct ValidateCommandOptions {
  std::vector<std::string> video_paths;
  int jobs = 1;  // videos measured at once (0: one per core)
  std::string plan_path;
  std::string output_directory;
  // Optional: the regulator's log (time_s, p1..pN in the plan's unit); its
  // holds give the test points' times, aligned to the video by the motion.
  std::string pressure_log_path;
  std::string constants_path;          // overrides the plan's
  std::optional<std::string> variant;  // overrides the plan's
  // Without times in the plan: seconds at rest at the start of the video.
  double rest_s = 1.0;
  // Read only the frames of the tests' windows, seeking between them (the
  // plan must give the times); trajectory.csv then holds those frames only.
  bool windows_only = false;
  bool no_registration = false;  // take the camera to be still
  // Take the heads' parallax out always, or never; by default where their
  // measured lifts show they leave the plane.
  bool lift_correction = false;
  bool no_lift_correction = false;
  bool decimal_comma = false;  // the pressure log writes 6,5 (declared)
  bool quiet = false;
  // Scoring and detection (no flags: their defaults are the thesis's).
  VideoValidationOptions validation;
};

// Exit status when the report was written but some tests are not scored:
// not measured (a window lost to damaged video data, beyond the video's
// end, a head not found, ...) or not moving as their plan entries predict.
// Each is named with its reason in the output, the report and results.csv.
inline constexpr int kExitSomeTestsNotScored = 3;

// Adds the command's flags to `command`, bound to `options`.
void AddValidateCommand(CLI::App* command, ValidateCommandOptions* options);
int RunValidate(const ValidateCommandOptions& options, std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_VALIDATE_COMMAND_H_
