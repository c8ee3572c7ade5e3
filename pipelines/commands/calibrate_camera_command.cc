#include "pipelines/commands/calibrate_camera_command.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "calibration/camera_calibration.h"
#include "util/atomic_file.h"
#include "util/input_error.h"
#include "util/progress.h"
#include "vision/video_reader.h"

namespace softbench {
namespace {

namespace fs = std::filesystem;

struct Views {
  std::vector<std::vector<cv::Point2f>> corners;
  cv::Size size;
  int looked_at = 0;
};

void AddView(const cv::Mat& gray, const std::string& where,
             const BoardOptions& board, Views* views) {
  if (views->size.empty()) views->size = gray.size();
  if (gray.size() != views->size) {
    throw InputError(fmt::format(
        "{}: {}x{} differs from the first view's {}x{}; calibrate one "
        "resolution at a time",
        where, gray.cols, gray.rows, views->size.width, views->size.height));
  }
  ++views->looked_at;
  std::vector<cv::Point2f> corners = FindBoardCorners(gray, board);
  if (!corners.empty()) views->corners.push_back(std::move(corners));
}

}  // namespace

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

namespace {

// The boards of every --every-s of the video.
void ViewsFromVideo(const CalibrateCameraCommandOptions& options,
                    const BoardOptions& board, Views* views) {
  const std::string& source = options.video_path;
  VideoReaderOptions reader_options;
  reader_options.want_bgr = false;
  VideoReader reader(options.video_path, reader_options);
  ProgressBar progress("boards", reader.info().frame_count, !options.quiet);
  VideoFrame frame;
  double next_s = 0.0;
  while (reader.Read(&frame)) {
    progress.Update(frame.index + 1);
    if (frame.time_s + 1e-9 < next_s) continue;
    next_s = frame.time_s + options.every_s;
    AddView(frame.luma, fmt::format("{} at t = {:.3f} s", source, frame.time_s),
            board, views);
  }
  progress.Finish();
}

// The boards of every PNG or JPEG image in --images, in name order.
void ViewsFromImages(const CalibrateCameraCommandOptions& options,
                     const BoardOptions& board, Views* views) {
  std::error_code error;
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(options.images_dir, error)) {
    std::string ext = entry.path().extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), ::tolower);
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") {
      files.push_back(entry.path());
    }
  }
  if (error) {
    throw InputError("--images: cannot list " + options.images_dir + " (" +
                     error.message() + ")");
  }
  std::sort(files.begin(), files.end());
  for (const fs::path& file : files) {
    const cv::Mat gray = cv::imread(file.string(), cv::IMREAD_GRAYSCALE);
    if (gray.empty()) {
      throw InputError(file.string() +
                       ": not a readable image; remove it or re-export it");
    }
    AddView(gray, file.string(), board, views);
  }
}

}  // namespace

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
  Views views;
  const std::string& source =
      options.video_path.empty() ? options.images_dir : options.video_path;
  if (!options.video_path.empty()) {
    ViewsFromVideo(options, calibration.board, &views);
  } else {
    ViewsFromImages(options, calibration.board, &views);
  }
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
