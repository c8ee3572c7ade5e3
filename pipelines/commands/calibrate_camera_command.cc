#include "pipelines/commands/calibrate_camera_command.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>

#include "calibration/camera_calibration.h"
#include "pipelines/commands/common_flags.h"
#include "pipelines/measurement/board_views.h"
#include "pipelines/reports/calibration_report.h"
#include "util/atomic_file.h"
#include "util/input_error.h"

namespace softbench {

void AddCalibrateCameraCommand(CLI::App* c,
                               CalibrateCameraCommandOptions* options) {
  c->add_option("source", options->source_path,
                "video of a checkerboard moved around the field, or a folder "
                "of checkerboard images (.png, .jpg)")
      ->required();
  c->add_option("--board", options->board,
                "inner corners per row x per column, e.g. 9x6")
      ->capture_default_str();
  c->add_option("--square-mm", options->square_mm,
                "side of one printed square, measured on the print [mm]")
      ->required();
  c->add_option("--every-s", options->every_s,
                "video: seconds between views used")
      ->capture_default_str();
  c->add_flag("--fit-k3", options->fit_k3,
              "also fit k3 (wide-angle lenses only)");
  AddOutOption(c, &options->output_path,
               "intrinsics YAML to write (OpenCV format)")
      ->required();
}

namespace {

// Each view's RMS reprojection error, the views without a board, and the
// views to consider dropping.
std::string ViewErrorsTable(const BoardViews& views,
                            const CameraCalibration& c) {
  const std::vector<std::string> outliers = OutlierViews(views, c);
  std::string table = "view  reprojection_error_px\n";
  for (size_t v = 0; v < c.view_errors_px.size() && v < views.names.size();
       ++v) {
    const bool outlier = std::find(outliers.begin(), outliers.end(),
                                   views.names[v]) != outliers.end();
    table += fmt::format("{}  {:.3f}{}\n", views.names[v], c.view_errors_px[v],
                         outlier ? "  <- far above the median" : "");
  }
  if (!views.missed.empty()) {
    table += fmt::format(
        "no whole board found in {} view{}: {}\n", views.missed.size(),
        views.missed.size() == 1 ? "" : "s", fmt::join(views.missed, ", "));
  }
  if (!outliers.empty()) {
    table += fmt::format(
        "consider removing {} (error over {:.0f}x the median view's) and "
        "calibrating again\n",
        fmt::join(outliers, ", "), kOutlierViewFactor);
  }
  return table;
}

// The page beside the intrinsics file: camera.yaml -> camera.html.
std::string PagePath(const std::string& output_path) {
  return std::filesystem::path(output_path).replace_extension(".html").string();
}

}  // namespace

int RunCalibrateCamera(const CalibrateCameraCommandOptions& options,
                       std::ostream& out) {
  CameraCalibrationOptions calibration;
  calibration.board = ParseBoardFlag(options.board, options.square_mm);
  calibration.fit_k3 = options.fit_k3;
  if (auto problem = calibration.Problem())
    throw InputError("--board: " + *problem);
  if (!(options.every_s > 0.0)) throw InputError("--every-s: must be > 0");
  CheckOutputFile(options.output_path, "--out");
  const std::string page_path = PagePath(options.output_path);
  CheckOutputsSpareInputs(
      {{"the views", options.source_path}},
      {{"--out", options.output_path}, {"the page", page_path}}, {});
  BoardViewsOptions view_options;
  view_options.board = calibration.board;
  view_options.every_s = options.every_s;
  view_options.progress = !options.quiet;
  const std::string& source = options.source_path;
  std::error_code error;
  const BoardViews views = std::filesystem::is_directory(source, error)
                               ? BoardViewsFromImages(source, view_options)
                               : BoardViewsFromVideo(source, view_options);
  if (const std::optional<cv::Size> printed = PrintedBoardSize(views);
      printed && !SameBoardSize(*printed, {calibration.board.corners_x,
                                           calibration.board.corners_y})) {
    throw InputError(fmt::format(
        "{}: the board in the views has {} x {} inner corners (counted in {} "
        "of the first {} views), not the {} x {} of --board; give --board "
        "{}x{}",
        source, printed->width, printed->height,
        std::count_if(
            views.counted.begin(), views.counted.end(),
            [&](const cv::Size& s) { return SameBoardSize(s, *printed); }),
        std::min(views.looked_at, view_options.counted_views),
        calibration.board.corners_x, calibration.board.corners_y,
        std::max(printed->width, printed->height),
        std::min(printed->width, printed->height)));
  }
  const CameraCalibrationSummary summary =
      CalibrateCamera(views.corners, views.size, calibration);
  if (!summary.converged) {
    throw InputError(fmt::format("{}: looked at {} views: {}", source,
                                 views.looked_at, summary.why_not));
  }
  const CameraCalibration& c = summary.calibration;
  const std::string page =
      CalibrationReportHtml(views, c, calibration.board, source);
  WriteFileAtomically(options.output_path, CameraCalibrationToYaml(c));
  WriteFileAtomically(page_path, page);
  out << ViewErrorsTable(views, c);
  out << fmt::format(
      "calibrated from {} of {} views of {}: fx {:.2f} fy {:.2f} cx {:.2f} "
      "cy {:.2f} px, k1 {:.5f} k2 {:.5f} p1 {:.6f} p2 {:.6f} k3 {:.5f}; "
      "reprojection error {:.3f} px RMS; written to {} (page: {})\n"
      "standard errors: fx {:.2f} fy {:.2f} cx {:.2f} cy {:.2f} px, k1 "
      "{:.5f} k2 {:.5f} p1 {:.6f} p2 {:.6f} k3 {:.5f}\n",
      c.views, views.looked_at, source, c.camera_matrix(0, 0),
      c.camera_matrix(1, 1), c.camera_matrix(0, 2), c.camera_matrix(1, 2),
      c.distortion[0], c.distortion[1], c.distortion[2], c.distortion[3],
      c.distortion[4], c.reprojection_error_px, options.output_path, page_path,
      c.intrinsics_std_px[0], c.intrinsics_std_px[1], c.intrinsics_std_px[2],
      c.intrinsics_std_px[3], c.distortion_std[0], c.distortion_std[1],
      c.distortion_std[2], c.distortion_std[3], c.distortion_std[4]);
  return 0;
}

}  // namespace softbench
