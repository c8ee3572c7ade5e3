// softbench: bench videos of soft pneumatic mechanisms to model-validation
// reports. This file only wires the subcommands to their Run functions.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <iostream>

#include "pipelines/calibrate_camera_command.h"
#include "pipelines/fit_command.h"
#include "pipelines/inverse_command.h"
#include "pipelines/predict_command.h"
#include "pipelines/render_command.h"
#include "pipelines/synth_forces_command.h"
#include "pipelines/track_command.h"
#include "pipelines/tune_command.h"
#include "pipelines/validate_command.h"
#include "pipelines/workspace_command.h"
#include "util/input_error.h"

namespace {

// Exit codes: 0 success, 1 internal failure, 2 bad input, 3 unreachable
// target (inverse), CLI11's own codes (>= 100) for malformed command lines.
constexpr int kExitInternal = 1;
constexpr int kExitInputError = 2;

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "softbench: soft pneumatic actuator mechanisms, from model to bench "
      "video"};
  app.require_subcommand(1);
  bool quiet = false;
  app.add_flag("--quiet,-q", quiet,
               "print errors only (no progress, no warnings)");

  softbench::PredictOptions predict;
  softbench::WorkspaceCommandOptions workspace;
  softbench::InverseCommandOptions inverse;
  softbench::RenderCommandOptions render;
  softbench::AddPredictCommand(&app, &predict);
  softbench::AddWorkspaceCommand(&app, &workspace);
  softbench::AddInverseCommand(&app, &inverse);
  softbench::AddRenderCommand(&app, &render);
  softbench::TrackCommandOptions track;
  softbench::AddTrackCommand(&app, &track);
  softbench::TuneCommandOptions tune;
  softbench::AddTuneCommand(&app, &tune);
  softbench::CalibrateCameraCommandOptions calibrate_camera;
  softbench::AddCalibrateCameraCommand(&app, &calibrate_camera);
  softbench::FitCommandOptions fit;
  softbench::AddFitCommand(&app, &fit);
  softbench::SynthForcesCommandOptions synth_forces;
  softbench::AddSynthForcesCommand(&app, &synth_forces);
  softbench::ValidateCommandOptions validate;
  softbench::AddValidateCommand(&app, &validate);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  }
  auto logger = spdlog::stderr_color_mt("softbench");
  logger->set_pattern("softbench: %l: %v");
  logger->set_level(quiet ? spdlog::level::err : spdlog::level::info);
  spdlog::set_default_logger(logger);

  try {
    if (app.got_subcommand("predict")) {
      return softbench::RunPredict(predict, std::cout);
    }
    if (app.got_subcommand("workspace")) {
      return softbench::RunWorkspace(workspace, std::cout);
    }
    if (app.got_subcommand("inverse")) {
      return softbench::RunInverse(inverse, std::cout);
    }
    if (app.got_subcommand("render")) {
      render.quiet = quiet;
      return softbench::RunRender(render, std::cout);
    }
    if (app.got_subcommand("track")) {
      track.quiet = quiet;
      return softbench::RunTrack(track, std::cout);
    }
    if (app.got_subcommand("tune")) {
      return softbench::RunTune(tune, std::cout);
    }
    if (app.got_subcommand("calibrate-camera")) {
      calibrate_camera.quiet = quiet;
      return softbench::RunCalibrateCamera(calibrate_camera, std::cout);
    }
    if (app.got_subcommand("fit")) {
      fit.quiet = quiet;
      return softbench::RunFit(fit, std::cout);
    }
    if (app.got_subcommand("validate")) {
      validate.quiet = quiet;
      return softbench::RunValidate(validate, std::cout);
    }
    if (app.got_subcommand("synth-forces")) {
      synth_forces.quiet = quiet;
      return softbench::RunSynthForces(synth_forces, std::cout);
    }
  } catch (const softbench::InputError& e) {
    spdlog::error("{}", e.what());
    return kExitInputError;
  } catch (const std::exception& e) {
    spdlog::critical("internal error: {}", e.what());
    return kExitInternal;
  }
  return kExitInternal;
}
