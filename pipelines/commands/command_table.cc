#include "pipelines/commands/command_table.h"

#include <memory>
#include <vector>

#include "pipelines/commands/calibrate_camera_command.h"
#include "pipelines/commands/fit_command.h"
#include "pipelines/commands/inverse_command.h"
#include "pipelines/commands/predict_command.h"
#include "pipelines/commands/render_command.h"
#include "pipelines/commands/synth_forces_command.h"
#include "pipelines/commands/targets_command.h"
#include "pipelines/commands/track_command.h"
#include "pipelines/commands/tune_command.h"
#include "pipelines/commands/validate_command.h"
#include "pipelines/commands/workspace_command.h"

namespace softbench {
namespace {

// A table row from a command's options struct, the function that adds its
// flags and the function that runs it. The options live as long as the run
// function; a `quiet` member, where the command has one, gets --quiet.
template <typename Options, typename Run>
Command MakeCommand(std::string_view name, std::string_view help,
                    void (*add)(CLI::App*, Options*), Run run) {
  return {name, help, [add, run](CLI::App* command) -> CommandRun {
            auto options = std::make_shared<Options>();
            add(command, options.get());
            return
                [options, run](const GlobalFlags& global, std::ostream& out) {
                  if constexpr (requires { options->quiet; }) {
                    options->quiet = global.quiet;
                  }
                  return run(*options, out);
                };
          }};
}

}  // namespace

std::span<const Command> Commands() {
  static const std::vector<Command> kCommands = {
      MakeCommand("predict",
                  "Equilibrium head positions for given actuator pressures",
                  &AddPredictCommand, &RunPredict),
      MakeCommand("workspace",
                  "Workspace map: every combination of pressure levels",
                  &AddWorkspaceCommand, &RunWorkspace),
      MakeCommand("inverse",
                  "Pressures that place the head(s) at a target position",
                  &AddInverseCommand, &RunInverse),
      MakeCommand(
          "render",
          "Render bench footage of a test plan, with exact ground truth",
          &AddRenderCommand, &RunRender),
      MakeCommand("track", "Measure every head in every frame of a bench video",
                  &AddTrackCommand, &RunTrack),
      MakeCommand("tune",
                  "Show one frame's colour segmentation and suggest HSV "
                  "bounds for a plan",
                  &AddTuneCommand, &RunTune),
      MakeCommand("targets",
                  "Print-ready AprilTag, checkerboard and dot stickers (PDF, "
                  "SVG) at exact size",
                  &AddTargetsCommand, &RunTargets),
      MakeCommand(
          "calibrate-camera",
          "Camera intrinsics and lens distortion from checkerboard views",
          &AddCalibrateCameraCommand, &RunCalibrateCamera),
      MakeCommand(
          "fit",
          "Fit the actuator constants from force-sensor logs (thesis ch. 3)",
          &AddFitCommand, &RunFit),
      MakeCommand("synth-forces",
                  "Synthetic force-sensor logs of the thesis's "
                  "characterisation protocol",
                  &AddSynthForcesCommand, &RunSynthForces),
      MakeCommand("validate",
                  "Bench video and test plan to a model-validation report",
                  &AddValidateCommand, &RunValidate),
  };
  return kCommands;
}

}  // namespace softbench
