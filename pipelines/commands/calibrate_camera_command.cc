#include "pipelines/commands/calibrate_camera_command.h"

#include <fmt/format.h>

#include <cstdio>

#include "calibration/camera_calibration.h"
#include "pipelines/measurement/board_views.h"
#include "util/atomic_file.h"
#include "util/input_error.h"

namespace softbench {

void AddCalibrateCameraCommand(CLI::App* c,
                               CalibrateCameraCommandOptions* options) {
  auto* video = c->add_option("--video", options->video_path,
                              "video of a checkerboard moved around the field");
  auto* images = c->add_option("--images", options->images_dir,
                               "folder of checkerboard images (.png, .jpg)");
  video->excludes(images);
  c->add_option("--board", options->board,
                "inner corners per row x per column, e.g. 9x6")
      ->capture_default_str();
  c->add_option("--square-mm", options->square_mm, "side of one square")
      ->capture_default_str();
  c->add_option("--every-s", options->every_s,
                "video: seconds between views used")
      ->capture_default_str();
  c->add_flag("--fit-k3", options->fit_k3,
              "also fit k3 (wide-angle lenses only)");
  c->add_option("--output", options->output_path,
                "intrinsics YAML to write (OpenCV format)")
      ->required();
}

int RunCalibrateCamera(const CalibrateCameraCommandOptions& options,
                       std::ostream& out) {
  CameraCalibrationOptions calibration;
  int cx = 0, cy = 0;
  char x = 0;
  if (std::sscanf(options.board.c_str(), "%d%c%d", &cx, &x, &cy) != 3 ||
      x != 'x') {
    throw InputError("--board: '" + options.board +
                     "' is not COLUMNSxROWS of inner corners, e.g. 9x6");
  }
  calibration.board = {cx, cy, options.square_mm};
  calibration.fit_k3 = options.fit_k3;
  if (auto problem = calibration.Check())
    throw InputError("--board: " + *problem);
  if (!(options.every_s > 0.0)) throw InputError("--every-s: must be > 0");
  if (options.video_path.empty() == options.images_dir.empty()) {
    throw InputError("give --video or --images (one of them)");
  }
  BoardViewsOptions view_options;
  view_options.board = calibration.board;
  view_options.every_s = options.every_s;
  view_options.progress = !options.quiet;
  const std::string& source =
      options.video_path.empty() ? options.images_dir : options.video_path;
  const BoardViews views =
      options.video_path.empty()
          ? BoardViewsFromImages(options.images_dir, view_options)
          : BoardViewsFromVideo(options.video_path, view_options);
  const CameraCalibrationSummary summary =
      CalibrateCamera(views.corners, views.size, calibration);
  if (!summary.converged) {
    throw InputError(fmt::format("{}: looked at {} views: {}", source,
                                 views.looked_at, summary.why_not));
  }
  const CameraCalibration& c = summary.calibration;
  WriteFileAtomically(options.output_path, CameraCalibrationToYaml(c));
  out << fmt::format(
      "calibrated from {} of {} views of {}: fx {:.2f} fy {:.2f} cx {:.2f} "
      "cy {:.2f} px, k1 {:.5f} k2 {:.5f} p1 {:.6f} p2 {:.6f} k3 {:.5f}; "
      "reprojection error {:.3f} px RMS; written to {}\n",
      c.views, views.looked_at, source, c.camera_matrix(0, 0),
      c.camera_matrix(1, 1), c.camera_matrix(0, 2), c.camera_matrix(1, 2),
      c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3],
      c.distortion[4], c.reprojection_error_px, options.output_path);
  return 0;
}

}  // namespace softbench
