#ifndef SOFTBENCH_PIPELINES_COMMANDS_CALIBRATE_CAMERA_COMMAND_H_
#define SOFTBENCH_PIPELINES_COMMANDS_CALIBRATE_CAMERA_COMMAND_H_

#include <CLI/CLI.hpp>
#include <ostream>
#include <string>

namespace softbench {

// `softbench calibrate-camera`: intrinsics and distortion from checkerboard
// views (a video or a folder of images), in OpenCV's YAML format.
struct CalibrateCameraCommandOptions {
  // A video of the board moved around, or a folder of its photos.
  std::string source_path;
  std::string board = "9x6";  // inner corners, columns x rows
  double square_mm = 0.0;     // required: the printed square, measured
  double every_s = 0.5;       // video: one view per this many seconds
  bool fit_k3 = false;
  std::string output_path;
  bool quiet = false;
};

// Adds the command's flags to `command`, bound to `options`.
void AddCalibrateCameraCommand(CLI::App* command,
                               CalibrateCameraCommandOptions* options);
int RunCalibrateCamera(const CalibrateCameraCommandOptions& options,
                       std::ostream& out);

}  // namespace softbench

#endif  // SOFTBENCH_PIPELINES_COMMANDS_CALIBRATE_CAMERA_COMMAND_H_
